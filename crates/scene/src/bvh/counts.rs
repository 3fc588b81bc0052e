//! Per-thread counts of what the single-ray traversals visit (feature `traversal-counts`): a
//! measure of a tree's shape that, unlike a timing, does not move with the machine's load, so
//! a change to the build or the collapse can be judged on this shared machine by the nodes and
//! packets a ray set visits (`cargo run --release -p caustica-scene --features
//! traversal-counts --example traversal_counts`). Without the feature the hooks are empty.

/// Nodes and leaf packets visited.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalCounts {
    /// Inner nodes whose child boxes were tested.
    pub nodes: u64,
    /// Leaf packets whose primitives were tested.
    pub packets: u64,
}

#[cfg(feature = "traversal-counts")]
thread_local! {
    static COUNTS: std::cell::Cell<TraversalCounts> =
        const { std::cell::Cell::new(TraversalCounts { nodes: 0, packets: 0 }) };
}

/// One node tested.
#[inline(always)]
pub(super) fn node() {
    #[cfg(feature = "traversal-counts")]
    COUNTS.with(|c| {
        let mut v = c.get();
        v.nodes += 1;
        c.set(v);
    });
}

/// One packet tested.
#[inline(always)]
pub(super) fn packet() {
    #[cfg(feature = "traversal-counts")]
    COUNTS.with(|c| {
        let mut v = c.get();
        v.packets += 1;
        c.set(v);
    });
}

/// This thread's counts since the last call, reset to zero.
#[cfg(feature = "traversal-counts")]
pub fn take() -> TraversalCounts {
    COUNTS.with(|c| c.replace(TraversalCounts::default()))
}
