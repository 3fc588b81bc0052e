//! A 2-D density-estimation testbed with known ground truth, after the synthetic photon
//! distribution of seed 000 sec. 4.3 (fig. 4.4): 48 000 photons on shapes with edges, ridges,
//! circular and rectangular outlines and a thin line "as dense as the other shapes".
//!
//! Every [`Distribution`] is a probability density on the unit square [0, 1]² (units: 1/area,
//! the square having area 1), known in closed form as f(x) = g(x) / ∫g, where the shape
//! function g(x) ∈ [0, 1] is dimensionless. A density estimator run on [`Distribution::sample`]
//! is judged against [`Distribution::density_image`] with [`ise`] / [`relative_ise`].
//!
//! All shapes keep a margin of at least 0.05 from the square's boundary, so no estimator sees
//! boundary bias from the ground truth itself. Shapes are made of disjoint pieces, rectangles
//! half-open ([x0, x1) × [y0, y1)) and discs closed, which matters only on sets of measure zero
//! and on the pixel grid for the thin line: it is exactly one pixel of the default 256 × 256
//! image wide, x ∈ [140/256, 141/256), so its pixel centres lie on it and the exact image shows
//! it at its true density.

use caustica_core::sampling::Pcg32;
use std::f64::consts::PI;

/// Photon count of seed 000 fig. 4.4.
pub const PAPER_SAMPLES: usize = 48_000;

/// Side (pixels) of the default image the testbed is laid out for: the thin line is one pixel
/// of this grid wide.
pub const DEFAULT_RESOLUTION: usize = 256;

/// Left edge of the thin line: pixel column 140 of the default 256-pixel grid.
const LINE_X0: f64 = 140.0 / 256.0;
/// Right edge (excluded) of the thin line.
const LINE_X1: f64 = 141.0 / 256.0;

/// One disjoint piece of a shape function.
#[derive(Clone, Copy, Debug)]
enum Part {
    /// g = `value` on [x0, x1) × [y0, y1).
    Rect {
        x0: f64,
        x1: f64,
        y0: f64,
        y1: f64,
        value: f64,
    },
    /// g = 1 on the closed annulus r0 ≤ |p − c| ≤ r1 (a disc when r0 = 0).
    Annulus { cx: f64, cy: f64, r0: f64, r1: f64 },
    /// g = sin²(count π t) on [x0, x1) × [y0, y1), with t = (x − x0)/(x1 − x0) (ridges parallel
    /// to y) or, if `horizontal`, t = (y − y0)/(y1 − y0) (ridges parallel to x): `count` smooth
    /// ridges of peak 1 that vanish at both ends of the block.
    Ridges {
        x0: f64,
        x1: f64,
        y0: f64,
        y1: f64,
        count: u32,
        horizontal: bool,
    },
    /// g = (x − x0)/(x1 − x0) on [x0, x1) × [y0, y1): a linear ramp from 0 to 1 in x.
    Ramp { x0: f64, x1: f64, y0: f64, y1: f64 },
}

impl Part {
    fn shape(&self, x: f64, y: f64) -> f64 {
        let inside = |x0: f64, x1: f64, y0: f64, y1: f64| x >= x0 && x < x1 && y >= y0 && y < y1;
        match *self {
            Part::Rect {
                x0,
                x1,
                y0,
                y1,
                value,
            } => {
                if inside(x0, x1, y0, y1) {
                    value
                } else {
                    0.0
                }
            }
            Part::Annulus { cx, cy, r0, r1 } => {
                let r2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
                if r2 >= r0 * r0 && r2 <= r1 * r1 {
                    1.0
                } else {
                    0.0
                }
            }
            Part::Ridges {
                x0,
                x1,
                y0,
                y1,
                count,
                horizontal,
            } => {
                if !inside(x0, x1, y0, y1) {
                    return 0.0;
                }
                let t = if horizontal {
                    (y - y0) / (y1 - y0)
                } else {
                    (x - x0) / (x1 - x0)
                };
                let s = (count as f64 * PI * t).sin();
                s * s
            }
            Part::Ramp { x0, x1, y0, y1 } => {
                if inside(x0, x1, y0, y1) {
                    (x - x0) / (x1 - x0)
                } else {
                    0.0
                }
            }
        }
    }

    /// ∫ g over the part, in closed form.
    fn integral(&self) -> f64 {
        match *self {
            Part::Rect {
                x0,
                x1,
                y0,
                y1,
                value,
            } => value * (x1 - x0) * (y1 - y0),
            Part::Annulus { r0, r1, .. } => PI * (r1 * r1 - r0 * r0),
            // sin² over a whole number of half periods averages 1/2; the ramp averages 1/2.
            Part::Ridges { x0, x1, y0, y1, .. } | Part::Ramp { x0, x1, y0, y1 } => {
                0.5 * (x1 - x0) * (y1 - y0)
            }
        }
    }

    /// Bounding box [x0, x1, y0, y1] of the part's support.
    fn bbox(&self) -> [f64; 4] {
        match *self {
            Part::Rect { x0, x1, y0, y1, .. }
            | Part::Ridges { x0, x1, y0, y1, .. }
            | Part::Ramp { x0, x1, y0, y1 } => [x0, x1, y0, y1],
            Part::Annulus { cx, cy, r1, .. } => [cx - r1, cx + r1, cy - r1, cy + r1],
        }
    }
}

/// A 2-D density on the unit square [0, 1]², known in closed form: f(x) = g(x) / ∫g, with
/// g(x) ∈ [0, 1] a shape function. Coordinates are in units of the square's side, densities in
/// 1/area; each shape's pieces are disjoint and stay at least 0.05 from the square's boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distribution {
    /// Uniform on the rectangle [0.25, 0.75) × [0.35, 0.65) (∫g = 0.15).
    Rectangle,
    /// Uniform in the disc of radius 0.3 about (0.5, 0.5) (∫g = 0.09π).
    Disc,
    /// Uniform in the annulus 0.2 ≤ r ≤ 0.3 about (0.5, 0.5) (∫g = 0.05π).
    Ring,
    /// Uniform on the thin vertical line [140/256, 141/256) × [0.15, 0.85): one pixel of the
    /// default 256-pixel grid wide, aligned to pixel edges (∫g = 0.7/256).
    Line,
    /// On [0.2, 0.8)², g = sin²(5π (x − 0.2)/0.6): five smooth parallel ridges along y, of peak
    /// 1, vanishing at x = 0.2 and 0.8 but with sharp ends at y = 0.2 and 0.8 (∫g = 0.18, half
    /// the block's area).
    Ridges,
    /// On [0.1, 0.9)², g = (x − 0.1)/0.8 rising linearly from 0 to 1: a soft gradient with
    /// sharp top, bottom and right sides (∫g = 0.32).
    Gradient,
    /// On [0.1, 0.9)², g = 1 for x < 0.5 and 0.25 for x ≥ 0.5: a sharp step of 4:1 down the
    /// middle (∫g = 0.4).
    Edge,
    /// The fig. 4.4 analogue: a disjoint union, all with peak g = 1 (so the thin line is as
    /// dense as the other shapes), of
    /// * a rectangle [0.08, 0.45) × [0.60, 0.90) (top left),
    /// * a disc of radius 0.18 about (0.25, 0.30) (bottom left),
    /// * the thin line [140/256, 141/256) × [0.15, 0.85) of [`Distribution::Line`] (centre),
    /// * a ring 0.10 ≤ r ≤ 0.16 about (0.77, 0.72) (top right),
    /// * a block [0.62, 0.92) × [0.10, 0.45) of five horizontal ridges,
    ///   g = sin²(5π (y − 0.10)/0.35), across the line's direction (bottom right).
    ///
    /// Bounding boxes do not overlap and stay ≥ 0.07 from the square's boundary;
    /// ∫g = 0.111 + 0.0324π + 0.0156π + 0.7/256 + 0.0525.
    Composite,
}

const RECTANGLE: [Part; 1] = [Part::Rect {
    x0: 0.25,
    x1: 0.75,
    y0: 0.35,
    y1: 0.65,
    value: 1.0,
}];
const DISC: [Part; 1] = [Part::Annulus {
    cx: 0.5,
    cy: 0.5,
    r0: 0.0,
    r1: 0.3,
}];
const RING: [Part; 1] = [Part::Annulus {
    cx: 0.5,
    cy: 0.5,
    r0: 0.2,
    r1: 0.3,
}];
const LINE: Part = Part::Rect {
    x0: LINE_X0,
    x1: LINE_X1,
    y0: 0.15,
    y1: 0.85,
    value: 1.0,
};
const RIDGES: [Part; 1] = [Part::Ridges {
    x0: 0.2,
    x1: 0.8,
    y0: 0.2,
    y1: 0.8,
    count: 5,
    horizontal: false,
}];
const GRADIENT: [Part; 1] = [Part::Ramp {
    x0: 0.1,
    x1: 0.9,
    y0: 0.1,
    y1: 0.9,
}];
const EDGE: [Part; 2] = [
    Part::Rect {
        x0: 0.1,
        x1: 0.5,
        y0: 0.1,
        y1: 0.9,
        value: 1.0,
    },
    Part::Rect {
        x0: 0.5,
        x1: 0.9,
        y0: 0.1,
        y1: 0.9,
        value: 0.25,
    },
];
const COMPOSITE: [Part; 5] = [
    Part::Rect {
        x0: 0.08,
        x1: 0.45,
        y0: 0.60,
        y1: 0.90,
        value: 1.0,
    },
    Part::Annulus {
        cx: 0.25,
        cy: 0.30,
        r0: 0.0,
        r1: 0.18,
    },
    LINE,
    Part::Annulus {
        cx: 0.77,
        cy: 0.72,
        r0: 0.10,
        r1: 0.16,
    },
    Part::Ridges {
        x0: 0.62,
        x1: 0.92,
        y0: 0.10,
        y1: 0.45,
        count: 5,
        horizontal: true,
    },
];

/// Uniform f64 in [0, 1) with 53 random bits, from two PCG32 outputs.
fn next_f64(rng: &mut Pcg32) -> f64 {
    let hi = rng.next_u32() as u64;
    let lo = rng.next_u32() as u64;
    ((hi << 21) | (lo >> 11)) as f64 * (1.0 / (1u64 << 53) as f64)
}

impl Distribution {
    pub const ALL: [Distribution; 8] = [
        Distribution::Rectangle,
        Distribution::Disc,
        Distribution::Ring,
        Distribution::Line,
        Distribution::Ridges,
        Distribution::Gradient,
        Distribution::Edge,
        Distribution::Composite,
    ];

    /// Lower-case name, as on a command line.
    pub fn name(self) -> &'static str {
        match self {
            Distribution::Rectangle => "rectangle",
            Distribution::Disc => "disc",
            Distribution::Ring => "ring",
            Distribution::Line => "line",
            Distribution::Ridges => "ridges",
            Distribution::Gradient => "gradient",
            Distribution::Edge => "edge",
            Distribution::Composite => "composite",
        }
    }

    /// Inverse of [`Distribution::name`].
    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|d| d.name() == s)
    }

    /// The disjoint pieces of the shape function.
    fn parts(self) -> &'static [Part] {
        match self {
            Distribution::Rectangle => &RECTANGLE,
            Distribution::Disc => &DISC,
            Distribution::Ring => &RING,
            Distribution::Line => std::slice::from_ref(&LINE),
            Distribution::Ridges => &RIDGES,
            Distribution::Gradient => &GRADIENT,
            Distribution::Edge => &EDGE,
            Distribution::Composite => &COMPOSITE,
        }
    }

    /// Bounding box [x0, x1, y0, y1] of the support of g.
    fn bbox(self) -> [f64; 4] {
        self.parts().iter().fold(
            [
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ],
            |b, p| {
                let q = p.bbox();
                [
                    b[0].min(q[0]),
                    b[1].max(q[1]),
                    b[2].min(q[2]),
                    b[3].max(q[3]),
                ]
            },
        )
    }

    /// Shape function g(x) in [0, 1] (dimensionless); 0 outside the shape, including outside the
    /// unit square.
    pub fn shape(self, x: f64, y: f64) -> f64 {
        // The parts are disjoint, so their sum is the union's shape function.
        self.parts().iter().map(|p| p.shape(x, y)).sum()
    }

    /// ∫ g over [0, 1]² in closed form (not numerically); units of area.
    pub fn shape_integral(self) -> f64 {
        self.parts().iter().map(Part::integral).sum()
    }

    /// Probability density f = g/∫g (1/area), at a point.
    pub fn density(self, x: f64, y: f64) -> f64 {
        self.shape(x, y) / self.shape_integral()
    }

    /// `n` points drawn from f, deterministic in `seed` (and different for different seeds).
    /// Rejection sampling: uniform proposals in the bounding box of the support, accepted with
    /// probability g, which gives density ∝ g because g vanishes outside the box.
    pub fn sample(self, n: usize, seed: u64) -> Vec<[f64; 2]> {
        let [x0, x1, y0, y1] = self.bbox();
        let mut rng = Pcg32::new(seed, 0x7e57_bed0 + self as u64);
        let mut out = Vec::with_capacity(n);
        while out.len() < n {
            let x = x0 + (x1 - x0) * next_f64(&mut rng);
            let y = y0 + (y1 - y0) * next_f64(&mut rng);
            // u < g never accepts a point with g = 0 (a proposal rounded onto an open edge).
            if next_f64(&mut rng) < self.shape(x, y) {
                out.push([x, y]);
            }
        }
        out
    }

    /// The exact density at the pixel centres of a width×height image of the unit square, row
    /// major, row 0 at y = 1 (top), pixel (i, j) centre at ((i+0.5)/w, 1-(j+0.5)/h).
    pub fn density_image(self, width: usize, height: usize) -> Vec<f64> {
        let mut out = Vec::with_capacity(width * height);
        for j in 0..height {
            let y = 1.0 - (j as f64 + 0.5) / height as f64;
            for i in 0..width {
                let x = (i as f64 + 0.5) / width as f64;
                out.push(self.density(x, y));
            }
        }
        out
    }
}

/// Neumaier's compensated sum: rounding error independent of the number of terms, so that an
/// image's ISE does not drift with its resolution.
fn compensated_sum(terms: impl Iterator<Item = f64>) -> f64 {
    let (mut sum, mut comp) = (0.0f64, 0.0f64);
    for t in terms {
        let s = sum + t;
        comp += if sum.abs() >= t.abs() {
            (sum - s) + t
        } else {
            (t - s) + sum
        };
        sum = s;
    }
    sum + comp
}

/// Integrated squared error ∫(f̂ − f)² over the unit square by the midpoint rule on the pixel
/// grid: the mean of the squared pixel differences, each pixel having area 1/(pixel count).
/// Both images hold values at pixel centres in the same layout (any width × height); units are
/// those of f², integrated over area (1/area for densities).
pub fn ise(estimate: &[f64], exact: &[f64]) -> f64 {
    assert_eq!(estimate.len(), exact.len(), "images differ in size");
    assert!(!exact.is_empty(), "empty image");
    compensated_sum(estimate.iter().zip(exact).map(|(e, f)| (e - f) * (e - f))) / exact.len() as f64
}

/// [`ise`] divided by ∫f² (midpoint rule on the same grid): dimensionless, 1 for the estimate
/// f̂ = 0 or 2f.
pub fn relative_ise(estimate: &[f64], exact: &[f64]) -> f64 {
    assert_eq!(estimate.len(), exact.len(), "images differ in size");
    assert!(!exact.is_empty(), "empty image");
    let norm = compensated_sum(exact.iter().map(|f| f * f)) / exact.len() as f64;
    ise(estimate, exact) / norm
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::chi2::chi_square;

    /// Midpoints and widths of a grid on [0, 1] that is uniform between consecutive `breaks`
    /// (0 and 1 are added), with about `per_unit` cells per unit length. Putting the shapes'
    /// edges among the breaks makes the midpoint rule exact for their straight sides, so what
    /// remains is the O(h²) error on smooth parts and the lattice error along circles.
    fn axis(mut breaks: Vec<f64>, per_unit: usize) -> Vec<(f64, f64)> {
        breaks.extend([0.0, 1.0]);
        breaks.retain(|b| (0.0..=1.0).contains(b));
        breaks.sort_by(f64::total_cmp);
        breaks.dedup();
        let mut out = Vec::new();
        for w in breaks.windows(2) {
            let (a, b) = (w[0], w[1]);
            let n = ((b - a) * per_unit as f64).ceil().max(1.0) as usize;
            let h = (b - a) / n as f64;
            out.extend((0..n).map(|k| (a + (k as f64 + 0.5) * h, h)));
        }
        out
    }

    /// ∫ `f` over each cell of a `cells` × `cells` grid of the unit square (index cx + cells·cy,
    /// cy counted from y = 0), by the midpoint rule on a grid aligned to the cells and to the
    /// distribution's edges.
    fn integrate_cells(
        d: Distribution,
        f: impl Fn(f64, f64) -> f64,
        cells: usize,
        per_unit: usize,
    ) -> Vec<f64> {
        let edges = (1..cells).map(|k| k as f64 / cells as f64);
        let (mut bx, mut by): (Vec<f64>, Vec<f64>) = edges.clone().zip(edges).unzip();
        for p in d.parts() {
            let [x0, x1, y0, y1] = p.bbox();
            bx.extend([x0, x1]);
            by.extend([y0, y1]);
        }
        if d == Distribution::Edge {
            bx.push(0.5);
        }
        let (ax, ay) = (axis(bx, per_unit), axis(by, per_unit));
        let cell = |t: f64| ((t * cells as f64) as usize).min(cells - 1);
        let mut out = vec![0.0; cells * cells];
        for &(x, wx) in &ax {
            let cx = cell(x);
            for &(y, wy) in &ay {
                out[cx + cells * cell(y)] += f(x, y) * wx * wy;
            }
        }
        out
    }

    #[test]
    fn names_round_trip() {
        for d in Distribution::ALL {
            assert_eq!(Distribution::from_name(d.name()), Some(d));
        }
        assert_eq!(Distribution::from_name("Disc"), None);
        assert_eq!(Distribution::from_name(""), None);
    }

    #[test]
    fn shape_integral_matches_numerical_integration() {
        // 4096 cells per unit, aligned to every straight edge (the thin line is its own strip of
        // 16 columns): the remaining error is far below the 1e-3 tolerance.
        for d in Distribution::ALL {
            let numeric = integrate_cells(d, |x, y| d.shape(x, y), 1, 4096)[0];
            let exact = d.shape_integral();
            let rel = (numeric - exact).abs() / exact;
            assert!(
                rel < 1e-3,
                "{}: closed form {exact}, numerical {numeric} (relative {rel:.2e})",
                d.name()
            );
        }
    }

    #[test]
    fn shape_is_in_unit_interval_and_keeps_a_margin() {
        let n = 512;
        for d in Distribution::ALL {
            let [x0, x1, y0, y1] = d.bbox();
            assert!(
                x0 >= 0.05 && y0 >= 0.05 && x1 <= 0.95 && y1 <= 0.95,
                "{d:?}"
            );
            let mut peak = 0.0f64;
            for j in 0..n {
                for i in 0..n {
                    let (x, y) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                    let g = d.shape(x, y);
                    assert!((0.0..=1.0).contains(&g), "{d:?}: g({x}, {y}) = {g}");
                    peak = peak.max(g);
                }
            }
            assert!(peak > 0.99, "{d:?}: peak {peak}");
        }
    }

    #[test]
    fn composite_parts_are_disjoint_with_equal_peaks() {
        for (a, p) in COMPOSITE.iter().enumerate() {
            let [ax0, ax1, ay0, ay1] = p.bbox();
            for q in &COMPOSITE[a + 1..] {
                let [bx0, bx1, by0, by1] = q.bbox();
                let apart = ax1 <= bx0 || bx1 <= ax0 || ay1 <= by0 || by1 <= ay0;
                assert!(apart, "{p:?} overlaps {q:?}");
            }
        }
        // The thin line is exactly as dense as the rectangle, disc and ring.
        let c = Distribution::Composite;
        let line = c.density((LINE_X0 + LINE_X1) / 2.0, 0.5);
        for (x, y) in [(0.2, 0.75), (0.25, 0.30), (0.77 + 0.13, 0.72)] {
            assert_eq!(c.density(x, y), line);
        }
        assert_eq!(line, 1.0 / c.shape_integral());
    }

    #[test]
    fn line_is_one_pixel_wide_on_the_default_grid() {
        let n = DEFAULT_RESOLUTION;
        let img = Distribution::Line.density_image(n, n);
        let f = 1.0 / Distribution::Line.shape_integral();
        for j in 0..n {
            for i in 0..n {
                let y = 1.0 - (j as f64 + 0.5) / n as f64;
                let on = i == 140 && (0.15..0.85).contains(&y);
                assert_eq!(img[i + n * j], if on { f } else { 0.0 }, "pixel ({i}, {j})");
            }
        }
    }

    #[test]
    fn density_image_layout_has_row_zero_at_the_top() {
        let (w, h) = (64, 32);
        for d in Distribution::ALL {
            let img = d.density_image(w, h);
            assert_eq!(img.len(), w * h);
            for j in 0..h {
                for i in 0..w {
                    let (x, y) = (
                        (i as f64 + 0.5) / w as f64,
                        1.0 - (j as f64 + 0.5) / h as f64,
                    );
                    assert_eq!(img[i + w * j], d.density(x, y), "{d:?} pixel ({i}, {j})");
                }
            }
        }
        // The composite's ring (hole at (0.77, 0.72)) is in the top rows, its ridges below.
        let c = Distribution::Composite.density_image(w, h);
        let at = |x: f64, y: f64| c[(x * w as f64) as usize + w * ((1.0 - y) * h as f64) as usize];
        assert_eq!(at(0.77, 0.72), 0.0);
        assert!(at(0.77, 0.28) > 0.0);
        // The edge is bright on the left.
        let e = Distribution::Edge.density_image(w, h);
        assert_eq!(e[10 + w * 16], 4.0 * e[50 + w * 16]);
    }

    #[test]
    fn density_integrates_to_one_on_the_pixel_grid() {
        // The midpoint rule on the pixel grid is exact on edges that lie on pixel edges and off
        // by less than one pixel row or column per pair of straight sides elsewhere, plus the
        // lattice error along circles. The worst case is the rectangle's 0.3-high side, which
        // covers 76.8 pixel rows of 256 and gets 76 (−1.04 %): allow 1.5 % at 256², and the
        // first-order convergence of that error, 0.4 % at 1024².
        for (n, tol) in [(DEFAULT_RESOLUTION, 0.015), (1024, 0.004)] {
            for d in Distribution::ALL {
                let img = d.density_image(n, n);
                let total = img.iter().sum::<f64>() / (n * n) as f64;
                assert!(
                    (total - 1.0).abs() < tol,
                    "{} at {n}²: ∫f = {total}",
                    d.name()
                );
            }
        }
    }

    #[test]
    fn sampling_matches_the_density() {
        // Pearson χ² of counts in 16×16 cells against n ∫_cell f (midpoint rule, 1024 cells per
        // unit aligned to the cells and the shapes' edges; error ≪ the √count noise), cells with
        // expected count below 5 pooled (caustica_core::chi2). Level 1e-4 per distribution
        // (about 8e-4 for the family of eight); fixed seed.
        const ALPHA: f64 = 1e-4;
        let cells = 16;
        let cell = |t: f64| ((t * cells as f64) as usize).min(cells - 1);
        let chi2 = |samples: &[[f64; 2]], d: Distribution| {
            let mut observed = vec![0.0; cells * cells];
            for &[x, y] in samples {
                observed[cell(x) + cells * cell(y)] += 1.0;
            }
            let expected: Vec<f64> = integrate_cells(d, |x, y| d.density(x, y), cells, 1024)
                .iter()
                .map(|p| p * samples.len() as f64)
                .collect();
            chi_square(&observed, &expected)
        };
        for d in Distribution::ALL {
            let samples = d.sample(PAPER_SAMPLES, 11);
            let r = chi2(&samples, d);
            assert!(r.passed_at(ALPHA), "{}: {r}", d.name());
        }
        // The test has power: samples of one shape fail against a similar density.
        for (drawn, claimed) in [
            (Distribution::Gradient, Distribution::Edge),
            (Distribution::Disc, Distribution::Ring),
            (Distribution::Ridges, Distribution::Rectangle),
        ] {
            let r = chi2(&drawn.sample(PAPER_SAMPLES, 11), claimed);
            assert!(!r.passed_at(ALPHA), "{drawn:?} vs {claimed:?}: {r}");
        }
    }

    #[test]
    fn sample_is_deterministic_in_seed_and_inside_the_shape() {
        for d in Distribution::ALL {
            let a = d.sample(2000, 3);
            assert_eq!(a.len(), 2000);
            assert_eq!(a, d.sample(2000, 3), "{d:?}");
            let b = d.sample(2000, 4);
            let same = a.iter().zip(&b).filter(|(p, q)| p == q).count();
            assert_eq!(same, 0, "{d:?}: seeds 3 and 4 share {same} points");
            for &[x, y] in &a {
                assert!(d.shape(x, y) > 0.0, "{d:?}: sample ({x}, {y}) has g = 0");
            }
        }
        assert!(Distribution::Line.sample(0, 1).is_empty());
    }

    #[test]
    fn ise_of_exact_and_offset_images() {
        let d = Distribution::Composite;
        let exact = d.density_image(DEFAULT_RESOLUTION, DEFAULT_RESOLUTION);
        assert_eq!(ise(&exact, &exact), 0.0);
        assert_eq!(relative_ise(&exact, &exact), 0.0);
        for c in [0.37, -2.5] {
            let shifted: Vec<f64> = exact.iter().map(|f| f + c).collect();
            let e = ise(&shifted, &exact);
            assert!((e - c * c).abs() < 1e-12 * c * c, "c = {c}: ise {e}");
        }
        // Relative ISE of 2f and of 0 is 1; of f + c it is c² / ∫f².
        let doubled: Vec<f64> = exact.iter().map(|f| 2.0 * f).collect();
        assert!((relative_ise(&doubled, &exact) - 1.0).abs() < 1e-12);
        let zero = vec![0.0; exact.len()];
        assert!((relative_ise(&zero, &exact) - 1.0).abs() < 1e-12);
        // On a non-square grid the pixel area is 1/(w h): a constant image c against 0 gives c².
        let (w, h) = (7, 3);
        assert!((ise(&vec![2.0; w * h], &vec![0.0; w * h]) - 4.0).abs() < 1e-15);
    }

    #[test]
    #[should_panic(expected = "differ in size")]
    fn ise_rejects_mismatched_sizes() {
        ise(&[0.0; 4], &[0.0; 5]);
    }
}
