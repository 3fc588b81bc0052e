//! Owen-scrambled Sobol points (Burley 2020) four dimensions at a time, from nibble tables:
//! the numbers of `sobol_burley::sample_4d`, bit for bit, at a fraction of the cost.
//!
//! `sample_4d` runs three steps: it shuffles the point index (an Owen scramble of its reversed
//! bits), multiplies it by the generator matrices of four dimensions (a loop over its set bits,
//! XOR-ing one direction vector per bit), and Owen-scrambles the result. Here
//!
//! * the shuffled index is computed once per stream ([`shuffled_index`]): it depends on the
//!   index and the seed only, not on the dimension, and a sampler draws many dimensions of one
//!   point;
//! * the matrix product, linear over XOR in the index bits, is four lookups of tables that
//!   hold it for every value of each 4-bit nibble of the 16 index bits used ([`Tables`],
//!   64 KiB), in place of a loop of data-dependent length whose branch a predictor loses;
//! * the final scramble is the crate's own (`sobol_burley::parts`).
//!
//! Photon paths draw most of their numbers here: the light tracer's instructions fall by 8 %,
//! the photon pass's by 5 % (docs/performance.md, issue 26, "Third session").

use sobol_burley::parts::{Int4, hash, hash_int4, owen_scramble_int4_rev, owen_scramble_rev};
use std::sync::OnceLock;

/// Dimensions with Sobol points (the rest of a path draws from PCG32).
pub const DIMENSIONS: u32 = sobol_burley::NUM_DIMENSIONS;
const SETS: usize = (DIMENSIONS / 4) as usize;

/// `table[set][k][v]`: the reversed-bit Sobol integers of the four dimensions of `set` for a
/// reversed index whose only set bits are nibble `k` of its top 16 bits, with value `v`.
struct Tables {
    table: Box<[[[[u32; 4]; 16]; 4]; SETS]>,
}

fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(|| {
        let mut table = vec![[[[0u32; 4]; 16]; 4]; SETS];
        for (set, nibbles) in table.iter_mut().enumerate() {
            for (k, values) in nibbles.iter_mut().enumerate() {
                for (v, out) in values.iter_mut().enumerate() {
                    let index_rev = (v as u32) << (16 + 4 * k);
                    *out = sobol_burley::parts::sobol_int4_rev(index_rev, set as u32).into();
                }
            }
        }
        Tables {
            table: table
                .into_boxed_slice()
                .try_into()
                .unwrap_or_else(|_| unreachable!("the table has SETS entries")),
        }
    })
}

/// The shuffled, bit-reversed index of point `index` (< 2¹⁶) of the sequence of `seed`:
/// `sample_4d`'s first step, the same for every dimension of the point.
#[inline]
pub fn shuffled_index(index: u32, seed: u32) -> u32 {
    owen_scramble_rev(index.reverse_bits(), hash(seed ^ 0x79c68e4a))
}

/// Dimensions `4 set .. 4 set + 4` (`set` < 64) of the point whose [`shuffled_index`] is
/// `shuffled`, in the sequence of `seed`: equal to `sobol_burley::sample_4d(index, set, seed)`.
#[inline]
pub fn sample_4d(shuffled: u32, set: u32, seed: u32) -> [f32; 4] {
    let t = &tables().table[set as usize % SETS];
    // The generator matrices are linear over XOR in the index bits: one lookup per nibble.
    let top = shuffled >> 16;
    let mut sobol = [0u32; 4];
    for (k, values) in t.iter().enumerate() {
        let v = &values[((top >> (4 * k)) & 15) as usize];
        for (s, x) in sobol.iter_mut().zip(v) {
            *s ^= x;
        }
    }
    // The crate's scramble of the result, step for step.
    let scramble = {
        let seed: Int4 = [seed.wrapping_mul(0x9c8f2d3b); 4].into();
        let ds: Int4 = [set; 4].into();
        seed ^ ds ^ [0x912f69ba, 0x174f18ab, 0x691e72ca, 0xb40cc1b8].into()
    };
    owen_scramble_int4_rev(sobol.into(), hash_int4(scramble))
        .reverse_bits()
        .to_f32_norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    /// The tables give the crate's numbers bit for bit: every dimension set, indices at the
    /// ends of the 16-bit range and random ones, random seeds.
    #[test]
    fn equals_the_crate_bit_for_bit() {
        let mut rng = Pcg32::new(17, 3);
        let mut indices: Vec<u32> = vec![0, 1, 2, 3, 0x8000, 0xFFFE, 0xFFFF];
        indices.extend((0..60).map(|_| rng.next_u32() & 0xFFFF));
        let mut checked = 0;
        for seed in [0u32, 1, 0xDEAD_BEEF, rng.next_u32(), rng.next_u32()] {
            for &i in &indices {
                let shuffled = shuffled_index(i, seed);
                for set in 0..SETS as u32 {
                    let want = sobol_burley::sample_4d(i, set, seed);
                    let got = sample_4d(shuffled, set, seed);
                    assert_eq!(
                        got.map(f32::to_bits),
                        want.map(f32::to_bits),
                        "index {i}, set {set}, seed {seed}"
                    );
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 5 * indices.len() * SETS);
    }
}
