//! The traversal stack: `(entry distance, node or packet)` in a fixed array declared by the
//! caller, spilling to the heap only for very deep trees.

use std::mem::MaybeUninit;

/// Entries kept in place before the stack spills to the heap.
pub(super) const STACK: usize = 64;

/// A stack's uninitialised storage, declared by the caller (building it inside `Stack::new`
/// made the compiler copy the whole array on every query). It is left uninitialised: zeroing
/// it cost more per ray than a shallow tree's whole traversal.
pub(super) type StackBuf = [MaybeUninit<(f32, u32)>; STACK];

pub(super) struct Stack<'a> {
    buf: &'a mut StackBuf,
    /// Entries `buf[..len]` are initialised (the invariant every method keeps).
    len: usize,
    spill: Vec<(f32, u32)>,
}

impl<'a> Stack<'a> {
    #[inline(always)]
    pub(super) fn new(buf: &'a mut StackBuf) -> Self {
        Self {
            buf,
            len: 0,
            spill: Vec::new(),
        }
    }

    #[inline(always)]
    pub(super) fn push(&mut self, e: (f32, u32)) {
        // Once spilled, later entries go to the heap too, so pops stay last-in first-out.
        match self.buf.get_mut(self.len) {
            Some(slot) if self.spill.is_empty() => {
                slot.write(e);
                self.len += 1;
            }
            _ => self.spill.push(e),
        }
    }

    #[inline(always)]
    pub(super) fn pop(&mut self) -> Option<(f32, u32)> {
        if let Some(e) = self.spill.pop() {
            return Some(e);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        // SAFETY: `len` counts the initialised prefix of `buf`: `push` writes `buf[len]` before
        // incrementing `len`, and only `pop` decrements it. Before this decrement `len ≥ 1`
        // entries were initialised, so `buf[len]` (the last of them) is initialised. The index
        // is in bounds because `len ≤ STACK` always holds (`push` only writes through `get_mut`).
        Some(unsafe { self.buf[self.len].assume_init() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stack_spills_and_stays_last_in_first_out() {
        let mut buf: StackBuf = [const { MaybeUninit::uninit() }; STACK];
        let mut s = Stack::new(&mut buf);
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
