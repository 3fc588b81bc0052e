//! Cache hints: asking the CPU for memory before it is read, so the loads of a traversal (its
//! children, its hit's record) overlap other work. Only arrays larger than the caches are
//! worth it ([`worth`]); in smaller ones the hints are extra instructions.

/// Arrays of more bytes than this are prefetched. Below it, prefetching every tree made the
/// light tracing of the three-primitive glass sphere 11 % slower, and a run-time check of the
/// hit-record hint cost the Cornell box 0.5 % more instructions (docs/performance.md).
const MIN_BYTES: usize = 1 << 20;

/// Whether reads of `data` are worth prefetching.
#[inline(always)]
pub(crate) fn worth<T>(data: &[T]) -> bool {
    std::mem::size_of_val(data) > MIN_BYTES
}

/// Asks for the cache lines of the `bytes` bytes from `p`, which starts a line.
#[inline(always)]
pub(crate) fn lines(p: *const u8, bytes: usize) {
    self::bytes(p, bytes, true);
}

/// Asks for every cache line of the `bytes` bytes from `p`; `aligned`: `p` starts a line (known
/// at compile time for line-aligned types, which then skip the rounding). A hint: it reads no
/// memory architecturally and never faults, whatever the address.
#[inline(always)]
fn bytes(p: *const u8, bytes: usize, aligned: bool) {
    #[cfg(target_arch = "x86_64")]
    {
        // From the start of `p`'s line, so an unaligned range gets its last line too.
        let skew = if aligned { 0 } else { p as usize & 63 };
        let line0 = p.wrapping_sub(skew);
        let end = skew + bytes;
        let mut off = 0;
        while off < end {
            // SAFETY: `prefetcht0` (SSE, in the x86_64 baseline) only hints the cache: it
            // reads no memory architecturally and cannot fault, whatever the address; the
            // address is formed with wrapping arithmetic, so no out-of-bounds pointer
            // arithmetic happens either.
            unsafe {
                use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
                _mm_prefetch::<_MM_HINT_T0>(line0.wrapping_add(off).cast());
            }
            off += 64;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (p, bytes, aligned);
}

/// Asks for element `i` of `data` (an index out of range is harmless: see [`bytes`]).
#[inline(always)]
pub(crate) fn element<T>(data: &[T], i: usize) {
    bytes(
        data.as_ptr().wrapping_add(i).cast(),
        std::mem::size_of::<T>(),
        std::mem::align_of::<T>() >= 64,
    );
}
