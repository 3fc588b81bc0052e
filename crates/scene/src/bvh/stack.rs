//! The traversal stack: `(entry distance, node or packet)` (with the eight-ray traversal's ray
//! mask, `(entry distance, node or packet, rays)`) in a fixed array declared by the caller,
//! spilling to the heap only for very deep trees. Pushing and popping within the array calls
//! nothing, so a traversal's hot loop can keep its ray in registers (every vector register is
//! saved around a call); spilling and refilling are out-of-line calls the loop leaves for.

use std::mem::MaybeUninit;

/// Entries kept in place before the stack spills to the heap. The crate's unit tests keep 16,
/// so that their traversals spill and refill all the time (a tree deep enough to spill 64 is
/// hard to build on purpose).
#[cfg(not(test))]
pub(super) const STACK: usize = 64;
#[cfg(test)]
pub(super) const STACK: usize = 16;

// A traversal spills when fewer than eight entries are free (a node's children); spilling half
// the array must then free at least eight.
const _: () = assert!(STACK >= 16);

/// A stack's uninitialised storage, declared by the caller (building it inside `Stack::new`
/// made the compiler copy the whole array on every query). It is left uninitialised: zeroing
/// it cost more per ray than a shallow tree's whole traversal.
pub(super) type StackBuf<T = (f32, u32)> = [MaybeUninit<T>; STACK];

pub(super) struct Stack<'a, T: Copy = (f32, u32)> {
    buf: &'a mut StackBuf<T>,
    /// Entries in `buf`: the first `len` are initialised (the invariant every method keeps),
    /// and they are the top of the stack.
    len: usize,
    /// The entries below those in `buf` (bottom first), moved out when `buf` filled up.
    spill: Vec<T>,
}

impl<'a, T: Copy> Stack<'a, T> {
    #[inline(always)]
    pub(super) fn new(buf: &'a mut StackBuf<T>) -> Self {
        Self {
            buf,
            len: 0,
            spill: Vec::new(),
        }
    }

    /// Free entries in the array: [`Self::push_within`] may be called that many times before
    /// [`Self::spill_half`].
    #[inline(always)]
    pub(super) fn room(&self) -> usize {
        STACK - self.len
    }

    /// Pushes `e` where [`Self::room`] is not zero (else `e` is lost). No call: the traversals'
    /// hot loops check the room first and spill outside the loop.
    #[inline(always)]
    pub(super) fn push_within(&mut self, e: T) {
        debug_assert!(self.len < STACK);
        if let Some(slot) = self.buf.get_mut(self.len) {
            slot.write(e);
            self.len += 1;
        }
    }

    /// Pops the top entry of the array; `None` when it is empty, though entries may wait in
    /// the spill ([`Self::refill`]).
    #[inline(always)]
    pub(super) fn pop_within(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        // SAFETY: `len ≤ STACK` always (`push_within` increments it only after writing
        // `buf[len]` with `len < STACK`; `spill_half` and `refill_from_spill` leave it at most
        // `STACK`), so after this decrement `len < STACK` and the index is in bounds. Entries
        // `0..len` of `buf` are initialised (those writes; `spill_half` and
        // `refill_from_spill` keep the first `len` written), and before the decrement `len`
        // was in `1..=STACK`, so `buf[len]` is one of them.
        Some(unsafe { self.buf.get_unchecked(self.len).assume_init() })
    }

    /// Pushes `e`, spilling first if the array is full.
    #[inline(always)]
    pub(super) fn push(&mut self, e: T) {
        if self.len == STACK {
            self.spill_half();
        }
        self.push_within(e);
    }

    /// Pops the top entry, refilling the array from the spill if it is empty.
    #[inline(always)]
    pub(super) fn pop(&mut self) -> Option<T> {
        if self.len == 0 && !self.refill() {
            return None;
        }
        self.pop_within()
    }

    /// Moves the bottom half of the array to the spill (the array must be full or nearly:
    /// deep trees only).
    #[cold]
    #[inline(never)]
    pub(super) fn spill_half(&mut self) {
        let half = self.len / 2;
        // SAFETY: entries `0..len` are initialised (the invariant).
        self.spill
            .extend(self.buf[..half].iter().map(|e| unsafe { e.assume_init() }));
        self.buf.copy_within(half..self.len, 0);
        self.len -= half;
    }

    /// Moves up to half an array of entries from the top of the spill into the empty array;
    /// false when the spill is empty too (the stack is empty: a call only where it is not).
    #[inline(always)]
    pub(super) fn refill(&mut self) -> bool {
        !self.spill.is_empty() && self.refill_from_spill()
    }

    /// [`Self::refill`] where the spill holds entries.
    #[cold]
    #[inline(never)]
    fn refill_from_spill(&mut self) -> bool {
        debug_assert_eq!(self.len, 0);
        let n = self.spill.len().min(STACK / 2);
        let from = self.spill.len() - n;
        for (slot, &e) in self.buf.iter_mut().zip(&self.spill[from..]) {
            slot.write(e);
        }
        self.spill.truncate(from);
        self.len = n;
        n > 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stack_spills_and_stays_last_in_first_out() {
        let mut buf: StackBuf = [const { MaybeUninit::uninit() }; STACK];
        let mut s: Stack = Stack::new(&mut buf);
        // Fill past the array, pop some, push again: pops must mirror pushes exactly.
        let mut model = Vec::new();
        for round in 0..3u32 {
            for i in 0..(STACK as u32 + 20) {
                let e = (i as f32, round * 1000 + i);
                s.push(e);
                model.push(e);
            }
            for _ in 0..30 {
                assert_eq!(s.pop(), model.pop());
            }
        }
        while let Some(e) = model.pop() {
            assert_eq!(s.pop(), Some(e));
        }
        assert_eq!(s.pop(), None);
    }

    #[test]
    fn the_traversals_protocol_stays_last_in_first_out() {
        // The hot loops' way: push within the array while there is room, else spill half
        // first; pop within the array, else refill it from the spill. Runs of pushes and pops
        // of random lengths reach several arrays deep.
        let mut buf: StackBuf<(u32, u32)> = [const { MaybeUninit::uninit() }; STACK];
        let mut s = Stack::new(&mut buf);
        let mut model = Vec::new();
        let mut rng = caustica_core::sampling::Pcg32::new(5, 9);
        let (mut spills, mut refills) = (0, 0);
        for step in 0..4000u32 {
            let n = rng.next_u32() % 24;
            if rng.next_u32() % 5 < 3 || model.len() < 8 {
                for i in 0..n {
                    if s.room() == 0 {
                        s.spill_half();
                        spills += 1;
                    }
                    s.push_within((step, i));
                    model.push((step, i));
                }
            } else {
                for _ in 0..n {
                    let got = match s.pop_within() {
                        Some(e) => Some(e),
                        None if s.refill() => {
                            refills += 1;
                            s.pop_within()
                        }
                        None => None,
                    };
                    assert_eq!(got, model.pop(), "step {step}");
                }
            }
        }
        assert!(model.len() > 3 * STACK, "depth {}", model.len());
        while let Some(e) = model.pop() {
            assert_eq!(s.pop(), Some(e));
        }
        assert_eq!(s.pop(), None);
        assert!(
            spills > 10 && refills > 10,
            "spills {spills}, refills {refills}"
        );
    }
}
