//! Bounding volume hierarchy (binned SAH build, stack traversal).

/// A BVH over primitive bounding boxes.
pub struct Bvh {}
