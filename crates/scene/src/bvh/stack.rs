//! The traversal stack: `(entry distance, node or packet)` (with the eight-ray traversal's ray
//! mask, `(entry distance, node or packet, rays)`) in a fixed array declared by the caller,
//! spilling to the heap only for very deep trees.

use std::mem::MaybeUninit;

/// Entries kept in place before the stack spills to the heap.
pub(super) const STACK: usize = 64;

/// A stack's uninitialised storage, declared by the caller (building it inside `Stack::new`
/// made the compiler copy the whole array on every query). It is left uninitialised: zeroing
/// it cost more per ray than a shallow tree's whole traversal.
pub(super) type StackBuf<T = (f32, u32)> = [MaybeUninit<T>; STACK];

pub(super) struct Stack<'a, T: Copy = (f32, u32)> {
    buf: &'a mut StackBuf<T>,
    /// Entries on the stack: the first `min(len, STACK)` in `buf[..]` (initialised, the
    /// invariant every method keeps), the rest in `spill`, in order.
    len: usize,
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

    #[inline(always)]
    pub(super) fn push(&mut self, e: T) {
        // One test on the common path: entries beyond the array go to the heap, in order.
        match self.buf.get_mut(self.len) {
            Some(slot) => {
                slot.write(e);
            }
            None => self.spill.push(e),
        }
        self.len += 1;
    }

    #[inline(always)]
    pub(super) fn pop(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        if self.len >= STACK {
            return self.spill.pop();
        }
        // SAFETY: entries `0..min(len, STACK)` of `buf` are initialised: `push` writes
        // `buf[len]` whenever `len < STACK` before incrementing `len`, and only `pop`
        // decrements it. Before this decrement `len` was in `1..=STACK` here, so `buf[len]`
        // (now the last entry) was written by the push that made it, and `len < STACK` keeps
        // the index in bounds.
        Some(unsafe { self.buf[self.len].assume_init() })
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
}
