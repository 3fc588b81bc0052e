//! The eye-path map: the first non-delta vertex of every camera sample — seen directly or
//! through mirrors and glass (paths D S* E) — with what is needed to add light arriving there
//! to its pixel: position, the direction toward the camera, the BSDF, the path throughput
//! ("importance") and the pixel index. Photon differential splatting (seed 002 sec. 3.3)
//! splats footprints onto it; progressive photon mapping's visible points (pbrt-v4's
//! `VisiblePoint`) are the same records.
//!
//! **Tiles.** The vertices are sorted into a locality-preserving order (k-d tree order) and cut
//! into tiles of [`TILE`] vertices, each with its own bounding box and k-d tree. The eye-splat
//! driver ([`crate::driver::eye_splat`]) runs over tiles in parallel: a tile takes the photons of
//! a batch in order, skips those whose box misses its own ([`EyeTile::for_each_in_box`]) and
//! adds the others to its own accumulators. No splat lists, no shared writes, and every vertex
//! sums its photons in photon order, so the image does not depend on the thread count and
//! memory does not depend on how many vertices a photon covers.

use crate::transport::vertex::Vertex;
use caustica_core::{Frame, Spectrum, Vec3};
use caustica_density::kdtree::KdTree;
use caustica_scene::bsdf::Bsdf;

/// One eye-path vertex: the first non-delta surface of a camera sample.
#[derive(Clone, Copy, Debug)]
pub struct EyeVertex {
    /// Position (m).
    pub p: Vec3,
    /// Geometric normal on the camera's side (unit).
    pub n: Vec3,
    /// Direction toward the camera, in the shading frame.
    pub wo: Vec3,
    pub frame: Frame,
    pub bsdf: Bsdf,
    /// Throughput of the camera path up to this vertex (the product of the delta vertices'
    /// weights and interior transmittances; 1 when seen directly).
    pub beta: Spectrum,
    /// Index `y · width + x` of the pixel whose sample this is.
    pub pixel: u32,
}

impl EyeVertex {
    /// The record of vertex `v` of a camera sample of pixel `pixel` with throughput `beta`.
    pub fn new(v: &Vertex, beta: Spectrum, pixel: u32) -> Self {
        Self {
            p: v.si.p,
            n: v.facing_normal(),
            wo: v.wo,
            frame: v.frame,
            bsdf: v.bsdf,
            beta,
            pixel,
        }
    }
}

/// Eye vertices per tile.
pub const TILE: usize = 1 << 13;

/// A spatially compact group of eye vertices with its bounding box and k-d tree.
pub struct EyeTile {
    pub vertices: Vec<EyeVertex>,
    tree: KdTree,
    lo: Vec3,
    hi: Vec3,
}

impl EyeTile {
    fn new(vertices: Vec<EyeVertex>) -> Self {
        let positions: Vec<Vec3> = vertices.iter().map(|v| v.p).collect();
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in positions.iter().filter(|p| p.is_finite()) {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        Self {
            tree: KdTree::build(&positions),
            vertices,
            lo,
            hi,
        }
    }

    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// Calls `f(i, vertex)` for every vertex `i` of the tile inside the box `[lo, hi]` (m), in
    /// the tile's tree order; nothing when the box misses the tile's bounding box.
    #[inline]
    pub fn for_each_in_box(&self, lo: Vec3, hi: Vec3, mut f: impl FnMut(usize, &EyeVertex)) {
        if lo.cmpgt(self.hi).any() || hi.cmplt(self.lo).any() {
            return;
        }
        self.tree
            .range_box(lo, hi, |i| f(i as usize, &self.vertices[i as usize]));
    }
}

/// The eye vertices of an image in tiles (see the module docs).
pub struct EyeMap {
    pub tiles: Vec<EyeTile>,
}

impl EyeMap {
    /// The map of `vertices` (any order; the map reorders them).
    pub fn new(vertices: Vec<EyeVertex>) -> Self {
        Self::with_tile_size(vertices, TILE)
    }

    /// [`EyeMap::new`] with `tile` vertices per tile (≥ 1).
    pub fn with_tile_size(vertices: Vec<EyeVertex>, tile: usize) -> Self {
        let positions: Vec<Vec3> = vertices.iter().map(|v| v.p).collect();
        let order: Vec<u32> = KdTree::build(&positions).indices_in_tree_order().collect();
        drop(positions);
        // Vertices with a non-finite position are not in the tree and can receive nothing.
        let sorted: Vec<EyeVertex> = order.iter().map(|&i| vertices[i as usize]).collect();
        drop(vertices);
        let tiles = sorted
            .chunks(tile.max(1))
            .map(|c| EyeTile::new(c.to_vec()))
            .collect();
        Self { tiles }
    }

    /// Number of eye vertices.
    pub fn len(&self) -> usize {
        self.tiles.iter().map(EyeTile::len).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Bytes held by the vertices and the trees.
    pub fn memory_bytes(&self) -> usize {
        self.tiles
            .iter()
            .map(|t| {
                std::mem::size_of::<EyeTile>()
                    + t.vertices.capacity() * std::mem::size_of::<EyeVertex>()
                    + t.tree.memory_bytes()
            })
            .sum()
    }
}
