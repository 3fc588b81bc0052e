//! RGB → spectrum upsampling by Jakob and Hanika's sigmoid polynomials (W. Jakob and
//! J. Hanika, "A Low-Dimensional Function Space for Efficient Spectral Upsampling",
//! Computer Graphics Forum 38(2), 2019), the method of Mitsuba 3 and pbrt-v4.
//!
//! A reflectance spectrum is s(λ) = S(x(λ)) with the sigmoid S(x) = ½ + x / (2 √(1 + x²)) ∈ (0, 1)
//! and the quadratic x(λ) = c₀ t² + c₁ t + c₂ in the **normalised wavelength**
//! t = (λ − 360 nm) / 470 nm ∈ [0, 1] (better conditioned in f32 than λ in nm). The three
//! coefficients of an RGB colour are those for which the linear sRGB colour of s(λ)·D65_n(λ)
//! is that colour, D65_n being D65 scaled to luminance 1 ([`super::cie::d65_n`]); so the
//! constant reflectance 1 is RGB (1, 1, 1), the colour space's white. They are found by
//! Newton's method on the 3×3 system ([`fit_coefficients`]), the colour integral taken by
//! Simpson's rule on [`QUAD_STEP_NM`] nm panels (whose edges fall on the D65 table's kinks).
//!
//! Renders look coefficients up in a table ([`RgbToSpectrumTable`], pbrt-v4's layout): the
//! largest RGB component selects one of three tables, the other two are divided by it (two
//! uniform axes in [0, 1]), and the largest itself is placed on a non-uniform axis
//! z_i = smoothstep(smoothstep(i / (res − 1))) that is dense near 0 and 1; the coefficients are
//! interpolated trilinearly. The table is solved by this module when first used (once per
//! process, [`srgb_table`], the three sub-tables on three scoped threads), walking each z column
//! up and down from z_{res/5} with every solve started from the linear extrapolation of its two
//! neighbours' answers (continuation, as in Jakob and Hanika's `rgb2spec_opt`), by a damped
//! Newton method that keeps its Jacobian while the residual falls fourfold per step.
//!
//! Resolution (measured by `measure_table_resolutions` below: process CPU time for the build;
//! round trip RGB → table → spectrum → RGB under D65_n on a 13³ grid of [0.05, 0.95]³, error in
//! units of the tolerance max(1 % relative, 0.005 absolute)):
//!
//! | res | build CPU | worst | worst relative  | mean relative |
//! |----:|----------:|------:|----------------:|--------------:|
//! | 16  |  0.03 s   | 3.05  | 30 %            | 0.92 %        |
//! | 24  |  0.12 s   | 0.70  | 7.0 % (of 0.05) | 0.36 %        |
//! | 32  |  0.24 s   | 0.54  | 5.4 % (of 0.05) | 0.27 %        |
//! | 48  |  0.75 s   | 0.23  | 2.3 %           | 0.14 %        |
//! | 64  |  1.66 s   | 0.12  | 1.2 %           | 0.09 %        |
//!
//! [`TABLE_RES`] = 32 keeps the build well under a second (about 0.1–0.2 s of wall time on two
//! cores) with every interior colour within the tolerance; the worst relative errors are on
//! components of 0.05 next to a large one (absolute error ≤ 0.003). One extra Newton step per
//! lookup would bring the worst to 0.017 of the tolerance but costs a colour-integral
//! evaluation (~0.5 µs) per lookup, too much per texel; [`RgbReflectance::new_exact`] does the
//! full fit for constants read once.
//!
//! Three spectrum types wrap the coefficients, pbrt-v4's three:
//! * [`RgbReflectance`] (albedos, in [0, 1]): s(λ) for RGB clamped to [0, 1];
//! * [`RgbUnbounded`] (any non-negative quantity, e.g. absorption coefficients): m·s(λ) with
//!   m = 2·max(RGB) and s fitted to RGB/m (whose largest component is ½);
//! * [`RgbIlluminant`] (emitters): m·s(λ)·D65_n(λ), so its linear sRGB colour is the RGB, and
//!   an emitter of RGB (1, 1, 1) renders the same in spectral and RGB mode.
//!
//! Negative components (outside sRGB's gamut; this model represents only its inside) and, for
//! reflectances, components above 1 are clamped; the `new_checked` constructors say whether
//! they clamped, so loaders can count and warn.

use std::sync::OnceLock;

use super::cie::{CIE_Y_INTEGRAL, LAMBDA_MAX, LAMBDA_MIN, XYZ_TO_LINEAR_SRGB, cie_xyz, d65_n};
use super::wavelengths::SampledWavelengths;
use crate::Spectrum;

/// Quadrature step of the colour integral the coefficients are fitted to (nm): Simpson panels
/// of this width for exact fits, the midpoint rule at this step for the table.
pub const QUAD_STEP_NM: f32 = 5.0;

/// Resolution of [`srgb_table`] along each of its three axes (see the module doc's table).
pub const TABLE_RES: usize = 32;

const SPAN_NM: f32 = LAMBDA_MAX - LAMBDA_MIN;

/// The sigmoid S(x) = ½ + x / (2 √(1 + x²)), with S(±∞) = 1, 0.
#[inline]
pub fn sigmoid(x: f32) -> f32 {
    if x.is_infinite() {
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

/// Evaluates the sigmoid polynomial of coefficients `c` (normalised wavelength, see the module
/// doc) at `lambda_nm`.
#[inline]
pub fn eval_coefficients(c: [f32; 3], lambda_nm: f32) -> f32 {
    let t = (lambda_nm - LAMBDA_MIN) * (1.0 / SPAN_NM);
    sigmoid((c[0] * t + c[1]) * t + c[2])
}

/// Coefficients of the constant spectrum `g` ∈ [0, 1]: x ≡ (g − ½)/√(g (1 − g)), so that
/// S(x) = g (±∞ at 0 and 1).
#[inline]
fn grey_coefficients(g: f32) -> [f32; 3] {
    let c2 = if g <= 0.0 {
        f32::NEG_INFINITY
    } else if g >= 1.0 {
        f32::INFINITY
    } else {
        (g - 0.5) / (g * (1.0 - g)).sqrt()
    };
    [0.0, 0.0, c2]
}

/// Quadrature of the colour integral: rgb(c) = Σ_i w_i S(x_c(t_i)), with
/// w_i = a_i M c̄(λ_i) D65_n(λ_i) / ∫ȳ (M: XYZ → linear sRGB) and a_i the weights of the
/// midpoint rule (`simpson == false`) or of composite Simpson panels (`simpson == true`; panels
/// of `step` nm, so the D65 table's kinks every 5 nm fall on panel edges when `step` divides 5).
struct Quadrature {
    /// Normalised node wavelengths t_i, padded with zero-weight nodes to a multiple of LANES.
    t: Vec<f64>,
    /// Weights per output channel (linear sRGB), same padding.
    w: [Vec<f64>; 3],
}

/// Independent partial sums per quadrature evaluation (lets the compiler use SIMD; 2 keeps the
/// 24 partial sums of [`Quadrature::eval`] in SSE registers, measured faster than 4).
const LANES: usize = 2;

impl Quadrature {
    fn new(step_nm: f32, simpson: bool) -> Self {
        let n = (SPAN_NM / step_nm).round().max(1.0) as usize; // intervals or panels
        let h = SPAN_NM as f64 / n as f64;
        let nodes: Vec<(f64, f64)> = if simpson {
            (0..=2 * n)
                .map(|i| {
                    let a = if i == 0 || i == 2 * n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    (LAMBDA_MIN as f64 + i as f64 * 0.5 * h, a * h / 6.0)
                })
                .collect()
        } else {
            (0..n)
                .map(|i| (LAMBDA_MIN as f64 + (i as f64 + 0.5) * h, h))
                .collect()
        };
        let (mut t, mut w) = (vec![], [vec![], vec![], vec![]]);
        for (l, a) in nodes {
            let c = cie_xyz(l as f32).map(|v| v as f64);
            let e = d65_n(l as f32) as f64 * a / CIE_Y_INTEGRAL as f64;
            for (k, wk) in w.iter_mut().enumerate() {
                let m = XYZ_TO_LINEAR_SRGB[k].map(|v| v as f64);
                wk.push((m[0] * c[0] + m[1] * c[1] + m[2] * c[2]) * e);
            }
            t.push((l - LAMBDA_MIN as f64) / SPAN_NM as f64);
        }
        while t.len() % 4 != 0 {
            t.push(0.0);
            for wk in w.iter_mut() {
                wk.push(0.0);
            }
        }
        Self { t, w }
    }

    /// Linear sRGB of S(x_c) under D65_n and its Jacobian d rgb / d c (rows: r, g, b).
    fn eval(&self, c: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        // acc[k][0] = Σ w_k S, acc[k][1 + j] = Σ w_k S' t^(2 − j), each in LANES partial sums.
        let mut acc = [[[0.0f64; LANES]; 4]; 3];
        for (i0, ts) in self.t.chunks_exact(LANES).enumerate() {
            let base = i0 * LANES;
            let mut s = [0.0; LANES];
            let mut g = [[0.0; LANES]; 3];
            for l in 0..LANES {
                let t = ts[l];
                let x = (c[0] * t + c[1]) * t + c[2];
                let d = 1.0 / (1.0 + x * x).sqrt();
                s[l] = 0.5 + 0.5 * x * d;
                let ds = 0.5 * d * d * d; // dS/dx
                g[2][l] = ds;
                g[1][l] = ds * t;
                g[0][l] = ds * t * t;
            }
            for (acc_k, w_k) in acc.iter_mut().zip(&self.w) {
                let w = &w_k[base..base + LANES];
                for l in 0..LANES {
                    acc_k[0][l] += w[l] * s[l];
                    acc_k[1][l] += w[l] * g[0][l];
                    acc_k[2][l] += w[l] * g[1][l];
                    acc_k[3][l] += w[l] * g[2][l];
                }
            }
        }
        let sum = |a: [f64; LANES]| a.iter().sum::<f64>();
        let rgb = [0, 1, 2].map(|k| sum(acc[k][0]));
        let jac = [0, 1, 2].map(|k| [sum(acc[k][1]), sum(acc[k][2]), sum(acc[k][3])]);
        (rgb, jac)
    }
}

impl Quadrature {
    /// Linear sRGB of S(x_c) under D65_n only (a quarter of [`Self::eval`]'s work).
    fn rgb(&self, c: [f64; 3]) -> [f64; 3] {
        let mut acc = [[0.0f64; 4]; 3];
        for (i0, ts) in self.t.chunks_exact(4).enumerate() {
            let base = i0 * 4;
            let mut s = [0.0; 4];
            for l in 0..4 {
                let t = ts[l];
                let x = (c[0] * t + c[1]) * t + c[2];
                s[l] = 0.5 + 0.5 * x / (1.0 + x * x).sqrt();
            }
            for (acc_k, w_k) in acc.iter_mut().zip(&self.w) {
                let w = &w_k[base..base + 4];
                for l in 0..4 {
                    acc_k[l] += w[l] * s[l];
                }
            }
        }
        acc.map(|a| a.iter().sum::<f64>())
    }
}

/// The quadrature of exact fits: Simpson on 5 nm panels (189 nodes; 0.04 % worst error
/// against a 1 nm reference, measured by `measure_quadrature_steps`).
fn quadrature() -> &'static Quadrature {
    static Q: OnceLock<Quadrature> = OnceLock::new();
    Q.get_or_init(|| Quadrature::new(QUAD_STEP_NM, true))
}

/// The quadrature the table is solved with: the midpoint rule at 5 nm (94 nodes), half the cost
/// of [`quadrature`] and 0.9 % worst relative (0.0004 absolute) error, below the table's
/// interpolation error (measured: worst round trip 0.54 vs 0.52 of the tolerance at res 32).
fn table_quadrature() -> &'static Quadrature {
    static Q: OnceLock<Quadrature> = OnceLock::new();
    Q.get_or_init(|| Quadrature::new(QUAD_STEP_NM, false))
}

/// Solves the 3×3 system `a x = b` by Cramer's rule; `None` when singular.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    if d.abs() <= 1e-300 || !d.is_finite() {
        return None;
    }
    let mut x = [0.0; 3];
    for (k, xk) in x.iter_mut().enumerate() {
        let mut m = a;
        for r in 0..3 {
            m[r][k] = b[r];
        }
        *xk = det(m) / d;
    }
    Some(x)
}

fn norm2(r: [f64; 3]) -> f64 {
    r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
}

/// Outcome of a fit: coefficients and the residual max-norm of the linear sRGB colour.
#[derive(Clone, Copy, Debug)]
pub struct Fit {
    pub coefficients: [f32; 3],
    /// max_k |rgb_k(c) − target_k|, in linear sRGB units.
    pub residual: f64,
    /// Newton iterations used.
    pub iterations: u32,
    /// Evaluations of the colour integral (with its Jacobian) used.
    pub evaluations: u32,
}

/// Damped Newton on rgb(c) = target from `start`: full steps while they reduce ‖r‖², halved
/// (at most 4 times) otherwise; steps longer than 50 (in coefficient units) are shortened,
/// which keeps the unreachable targets on the gamut's boundary (a component exactly 0 needs
/// infinite coefficients) finite.
fn newton(q: &Quadrature, target: [f64; 3], start: [f64; 3], max_iter: u32, tol: f64) -> Fit {
    let residual = |rgb: [f64; 3]| [0, 1, 2].map(|k| rgb[k] - target[k]);
    let mut c = start;
    let mut evals = 1;
    let (rgb, mut jac) = q.eval(c);
    let mut r = residual(rgb);
    // Whether `jac` was evaluated at `c` (else it is from an earlier iterate: a chord step).
    let mut fresh = true;
    let mut it = 0;
    while it < max_iter && r.iter().any(|v| v.abs() > tol) {
        it += 1;
        let Some(mut step) = solve3(jac, r.map(|v| -v)) else {
            break;
        };
        let len = step.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if len > 50.0 {
            step = step.map(|v| v * 50.0 / len);
        }
        let e0 = norm2(r);
        let mut alpha = 1.0;
        let mut accepted = false;
        for _ in 0..5 {
            let cn = [0, 1, 2].map(|k| c[k] + alpha * step[k]);
            let rn = residual(q.rgb(cn));
            evals += 1;
            let en = norm2(rn);
            if en < e0 {
                (c, r) = (cn, rn);
                accepted = true;
                // Keep the Jacobian while it converges fast (residual at least quartered).
                if en > 0.0625 * e0 {
                    let (rgb, j) = q.eval(c);
                    evals += 1;
                    (r, jac, fresh) = (residual(rgb), j, true);
                } else {
                    fresh = false;
                }
                break;
            }
            if !fresh {
                break; // retry from `c` with the Jacobian at `c`
            }
            alpha *= 0.5;
        }
        if !accepted {
            if fresh {
                break;
            }
            let (rgb, j) = q.eval(c);
            evals += 1;
            (r, jac, fresh) = (residual(rgb), j, true);
        }
    }
    Fit {
        coefficients: c.map(|v| v as f32),
        residual: r.iter().fold(0.0f64, |m, v| m.max(v.abs())),
        iterations: it,
        evaluations: evals,
    }
}

/// The exact fit of one colour: the coefficients whose sigmoid spectrum under D65_n has linear
/// sRGB colour `rgb` (clamped to [0, 1]), by Newton's method started from the table's answer
/// (or from grey) to a residual of 1e-7. Costs tens of microseconds; for load-time constants
/// and tests, not per-texel lookups (use [`RgbToSpectrumTable::lookup`]).
pub fn fit_coefficients(rgb: [f32; 3]) -> Fit {
    let rgb = rgb.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) });
    if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
        return Fit {
            coefficients: grey_coefficients(rgb[0]),
            residual: 0.0,
            iterations: 0,
            evaluations: 0,
        };
    }
    let start = srgb_table().lookup(rgb).map(|v| v as f64);
    let target = rgb.map(|v| v as f64);
    let f = newton(quadrature(), target, start, 30, 1e-7);
    if f.residual <= 1e-6 {
        return f;
    }
    // Fall back to a start from grey (the table's cell may straddle the gamut boundary).
    let g = newton(quadrature(), target, [0.0; 3], 60, 1e-7);
    if g.residual < f.residual { g } else { f }
}

/// The coefficient table of pbrt-v4's layout (see the module doc), solved at construction.
pub struct RgbToSpectrumTable {
    res: usize,
    /// z_i = smoothstep(smoothstep(i / (res − 1))), increasing from 0 to 1.
    z_nodes: Vec<f32>,
    /// Coefficients indexed `[((max_channel · res + zi) · res + yi) · res + xi]`.
    coeffs: Vec<[f32; 3]>,
}

fn smoothstep(x: f64) -> f64 {
    x * x * (3.0 - 2.0 * x)
}

impl RgbToSpectrumTable {
    /// Solves a table of `res` nodes per axis (res ≥ 3): 3·res³ Newton fits, each started
    /// from its neighbour on the z axis.
    pub fn build(res: usize) -> Self {
        Self::build_counted(res).0
    }

    /// [`Self::build`], also returning the number of evaluations of the colour integral.
    fn build_counted(res: usize) -> (Self, u64) {
        assert!(res >= 3, "table resolution {res}");
        let z_nodes: Vec<f64> = (0..res)
            .map(|i| smoothstep(smoothstep(i as f64 / (res - 1) as f64)))
            .collect();
        // The three tables are independent: one scoped thread each.
        let parts: Vec<(Vec<[f32; 3]>, u64)> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..3)
                .map(|l| {
                    let z_nodes = &z_nodes;
                    scope.spawn(move || Self::build_channel(res, l, z_nodes))
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("table build thread panicked"))
                .collect()
        });
        let evaluations = parts.iter().map(|p| p.1).sum();
        let coeffs = parts.into_iter().flat_map(|p| p.0).collect();
        let table = Self {
            res,
            z_nodes: z_nodes.iter().map(|&z| z as f32).collect(),
            coeffs,
        };
        (table, evaluations)
    }

    /// The table of colours whose largest component is channel `l`, indexed
    /// `[(zi · res + yi) · res + xi]`, and the number of colour-integral evaluations it took.
    fn build_channel(res: usize, l: usize, z_nodes: &[f64]) -> (Vec<[f32; 3]>, u64) {
        let q = table_quadrature();
        let mut coeffs = vec![[0.0f32; 3]; res * res * res];
        let mut evaluations = 0u64;
        let start = res / 5;
        for yi in 0..res {
            let y = yi as f64 / (res - 1) as f64;
            for xi in 0..res {
                let x = xi as f64 / (res - 1) as f64;
                let at = |zi: usize| (zi * res + yi) * res + xi;
                // Walk up from `start`, then down from it to z_1, each solve started from the
                // linear extrapolation (in z) of the previous two answers (continuation).
                let up: Vec<usize> = (start..res).collect();
                let down: Vec<usize> = (1..start).rev().collect();
                for walk in [up, down] {
                    // (z, coefficients) of the last two solves, most recent last.
                    let mut hist: Vec<(f64, [f64; 3])> = vec![];
                    for zi in walk {
                        let z = z_nodes[zi];
                        let guess = match hist.as_slice() {
                            [.., (z0, c0), (z1, c1)] => {
                                let a = (z - z1) / (z1 - z0);
                                [0, 1, 2].map(|k| c1[k] + a * (c1[k] - c0[k]))
                            }
                            [.., (_, c1)] => *c1,
                            [] => [0.0; 3],
                        };
                        let mut rgb = [0.0; 3];
                        rgb[l] = z;
                        rgb[(l + 1) % 3] = x * z;
                        rgb[(l + 2) % 3] = y * z;
                        // Relative tolerance 1e-6: below the f32 rounding of the coefficients'
                        // effect and far below the interpolation error.
                        let f = newton(q, rgb, guess, 15, 1e-6 * z);
                        evaluations += f.evaluations as u64;
                        coeffs[at(zi)] = f.coefficients;
                        hist.push((z, f.coefficients.map(|v| v as f64)));
                    }
                }
                // z_0 = 0 is black, which needs infinite coefficients; lookups below z_1
                // (≈ 1e-4 at res 32) reuse z_1's spectrum shape, an error below z_1 in
                // absolute value. (Pure black is handled as a grey.)
                coeffs[at(0)] = coeffs[at(1)];
            }
        }
        (coeffs, evaluations)
    }

    /// Nodes per axis.
    pub fn resolution(&self) -> usize {
        self.res
    }

    /// Coefficients for `rgb` ∈ [0, 1]³ (not checked; clamp first) by trilinear interpolation;
    /// greys get the exact constant ([`grey_coefficients`]).
    pub fn lookup(&self, rgb: [f32; 3]) -> [f32; 3] {
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            return grey_coefficients(rgb[0]);
        }
        let l = if rgb[0] > rgb[1] {
            if rgb[0] > rgb[2] { 0 } else { 2 }
        } else if rgb[1] > rgb[2] {
            1
        } else {
            2
        };
        let res = self.res;
        let z = rgb[l];
        let scale = (res - 1) as f32 / z;
        let x = rgb[(l + 1) % 3] * scale;
        let y = rgb[(l + 2) % 3] * scale;
        let xi = (x as usize).min(res - 2);
        let yi = (y as usize).min(res - 2);
        // Largest zi with z_nodes[zi] <= z, at most res − 2.
        let zi = self
            .z_nodes
            .partition_point(|&n| n <= z)
            .saturating_sub(1)
            .min(res - 2);
        let dx = x - xi as f32;
        let dy = y - yi as f32;
        let dz = (z - self.z_nodes[zi]) / (self.z_nodes[zi + 1] - self.z_nodes[zi]);
        let at =
            |zz: usize, yy: usize, xx: usize| self.coeffs[((l * res + zz) * res + yy) * res + xx];
        let mut out = [0.0f32; 3];
        for (k, o) in out.iter_mut().enumerate() {
            let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
            let c00 = lerp(dx, at(zi, yi, xi)[k], at(zi, yi, xi + 1)[k]);
            let c01 = lerp(dx, at(zi, yi + 1, xi)[k], at(zi, yi + 1, xi + 1)[k]);
            let c10 = lerp(dx, at(zi + 1, yi, xi)[k], at(zi + 1, yi, xi + 1)[k]);
            let c11 = lerp(dx, at(zi + 1, yi + 1, xi)[k], at(zi + 1, yi + 1, xi + 1)[k]);
            *o = lerp(dz, lerp(dy, c00, c01), lerp(dy, c10, c11));
        }
        out
    }
}

/// The process-wide linear-sRGB table at [`TABLE_RES`], solved on first use.
pub fn srgb_table() -> &'static RgbToSpectrumTable {
    static T: OnceLock<RgbToSpectrumTable> = OnceLock::new();
    T.get_or_init(|| RgbToSpectrumTable::build(TABLE_RES))
}

/// Clamps to [0, hi] (NaN → 0) and says whether anything changed.
#[inline]
fn clamp_rgb(rgb: [f32; 3], hi: f32) -> ([f32; 3], bool) {
    let mut clamped = false;
    let out = rgb.map(|v| {
        let c = if v.is_nan() { 0.0 } else { v.clamp(0.0, hi) };
        clamped |= c != v || v.is_nan();
        c
    });
    (out, clamped)
}

/// The spectrum's values at the three wavelengths of a path, as a [`Spectrum`] (lane j at
/// `wl.lambda[j]`).
#[inline]
pub fn sample3(f: impl Fn(f32) -> f32, wl: &SampledWavelengths) -> Spectrum {
    Spectrum::new(f(wl.lambda[0]), f(wl.lambda[1]), f(wl.lambda[2]))
}

/// A reflectance (albedo) spectrum in [0, 1] upsampled from linear sRGB in [0, 1]³.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbReflectance {
    coeffs: [f32; 3],
}

impl RgbReflectance {
    /// Upsamples `rgb` (linear sRGB, clamped to [0, 1]) by the table.
    #[inline]
    pub fn new(rgb: [f32; 3]) -> Self {
        Self::new_checked(rgb).0
    }

    /// As [`Self::new`], also saying whether `rgb` had to be clamped (a component below 0,
    /// above 1, or NaN).
    #[inline]
    pub fn new_checked(rgb: [f32; 3]) -> (Self, bool) {
        let (rgb, clamped) = clamp_rgb(rgb, 1.0);
        (
            Self {
                coeffs: srgb_table().lookup(rgb),
            },
            clamped,
        )
    }

    /// Upsamples `rgb` by an exact Newton fit ([`fit_coefficients`]) instead of the table:
    /// slower (microseconds), for constants read once.
    pub fn new_exact(rgb: [f32; 3]) -> Self {
        Self {
            coeffs: fit_coefficients(rgb).coefficients,
        }
    }

    /// The sigmoid polynomial's coefficients (normalised wavelength, see the module doc).
    pub fn coefficients(&self) -> [f32; 3] {
        self.coeffs
    }

    /// Reflectance at `lambda_nm` (nm), in [0, 1].
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        eval_coefficients(self.coeffs, lambda_nm)
    }

    /// Reflectance at a path's three wavelengths.
    #[inline]
    pub fn sample(&self, wl: &SampledWavelengths) -> Spectrum {
        sample3(|l| self.eval(l), wl)
    }
}

/// An unbounded non-negative spectrum (pbrt-v4's `RGBUnboundedSpectrum`): m·s(λ) with
/// m = 2·max(rgb) and s fitted to rgb/m, whose largest component is ½ (the middle of the
/// reflectance gamut, where the sigmoid fits best). Its linear sRGB colour under D65_n is `rgb`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbUnbounded {
    scale: f32,
    coeffs: [f32; 3],
}

impl RgbUnbounded {
    /// Upsamples `rgb` (negative components clamped to 0).
    #[inline]
    pub fn new(rgb: [f32; 3]) -> Self {
        Self::new_checked(rgb).0
    }

    /// As [`Self::new`], also saying whether a component was negative, infinite or NaN.
    #[inline]
    pub fn new_checked(rgb: [f32; 3]) -> (Self, bool) {
        let (rgb, clamped) = clamp_rgb(rgb, f32::MAX);
        let m = rgb[0].max(rgb[1]).max(rgb[2]);
        let scale = 2.0 * m;
        let coeffs = if scale > 0.0 && scale.is_finite() {
            srgb_table().lookup(rgb.map(|v| (v / scale).min(0.5)))
        } else {
            grey_coefficients(0.0)
        };
        (
            Self {
                scale: if scale.is_finite() { scale } else { 0.0 },
                coeffs,
            },
            clamped,
        )
    }

    /// The scale m = 2·max(rgb).
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// Value at `lambda_nm` (nm), in [0, m].
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        self.scale * eval_coefficients(self.coeffs, lambda_nm)
    }

    /// Values at a path's three wavelengths.
    #[inline]
    pub fn sample(&self, wl: &SampledWavelengths) -> Spectrum {
        sample3(|l| self.eval(l), wl)
    }
}

/// An emission spectrum from RGB radiance (pbrt-v4's `RGBIlluminantSpectrum`):
/// m·s(λ)·D65_n(λ) with m, s as in [`RgbUnbounded`]. Its linear sRGB colour is `rgb`; RGB
/// (1, 1, 1) is exactly D65_n, the spectrum that the film turns into (1, 1, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbIlluminant {
    inner: RgbUnbounded,
}

impl RgbIlluminant {
    /// Upsamples `rgb` radiance (negative components clamped to 0).
    #[inline]
    pub fn new(rgb: [f32; 3]) -> Self {
        Self::new_checked(rgb).0
    }

    /// As [`Self::new`], also saying whether a component was negative, infinite or NaN.
    #[inline]
    pub fn new_checked(rgb: [f32; 3]) -> (Self, bool) {
        let (inner, clamped) = RgbUnbounded::new_checked(rgb);
        (Self { inner }, clamped)
    }

    /// Spectral radiance at `lambda_nm` (nm), in caustica's spectral units (see the module doc
    /// of [`super`]).
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        self.inner.eval(lambda_nm) * d65_n(lambda_nm)
    }

    /// Values at a path's three wavelengths.
    #[inline]
    pub fn sample(&self, wl: &SampledWavelengths) -> Spectrum {
        sample3(|l| self.eval(l), wl)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectral::cie::{spectrum_to_xyz, xyz_to_linear_srgb};

    /// Linear sRGB of `s`·D65_n by the 1 nm reference quadrature (independent of the fit's).
    fn rgb_under_d65(s: impl Fn(f32) -> f32) -> [f32; 3] {
        xyz_to_linear_srgb(spectrum_to_xyz(|l| s(l) * d65_n(l)))
    }

    fn rgb_of(s: impl Fn(f32) -> f32) -> [f32; 3] {
        xyz_to_linear_srgb(spectrum_to_xyz(s))
    }

    fn close(got: [f32; 3], want: [f32; 3], rel: f32, abs: f32) -> bool {
        (0..3).all(|k| (got[k] - want[k]).abs() <= (rel * want[k].abs()).max(abs))
    }

    /// The grid of interior colours the round trip is tested on.
    fn interior_grid(n: usize) -> Vec<[f32; 3]> {
        let v = |i: usize| 0.05 + 0.9 * i as f32 / (n - 1) as f32;
        let mut out = vec![];
        for r in 0..n {
            for g in 0..n {
                for b in 0..n {
                    out.push([v(r), v(g), v(b)]);
                }
            }
        }
        out
    }

    #[test]
    fn reflectance_round_trip_over_the_gamut_interior() {
        let mut worst = (0.0f32, [0.0f32; 3]);
        for rgb in interior_grid(7) {
            let s = RgbReflectance::new(rgb);
            let got = rgb_under_d65(|l| s.eval(l));
            for k in 0..3 {
                let e = (got[k] - rgb[k]).abs() / (rgb[k] * 0.01).max(0.005);
                if e > worst.0 {
                    worst = (e, rgb);
                }
            }
            assert!(close(got, rgb, 0.01, 0.005), "{rgb:?} -> {got:?}");
        }
        eprintln!("worst round trip (in units of the tolerance): {worst:?}");
    }

    #[test]
    fn exact_fit_round_trip() {
        for rgb in interior_grid(4)
            .into_iter()
            .chain([[0.9, 0.05, 0.05], [0.02, 0.8, 0.3]])
        {
            let f = fit_coefficients(rgb);
            assert!(f.residual < 1e-6, "{rgb:?}: {f:?}");
            let got = rgb_under_d65(|l| eval_coefficients(f.coefficients, l));
            // Only the quadrature differs (5 nm midpoint vs 1 nm): well within 0.1 %.
            assert!(close(got, rgb, 1e-3, 5e-4), "{rgb:?} -> {got:?}");
        }
    }

    #[test]
    fn greys_are_flat_and_reflectances_bounded() {
        for g in [0.0f32, 0.01, 0.18, 0.5, 0.73, 0.99, 1.0] {
            let s = RgbReflectance::new([g; 3]);
            let v0 = s.eval(360.0);
            for l in (360..=830).step_by(10) {
                assert_eq!(s.eval(l as f32), v0, "grey {g} at {l}");
            }
            assert!((v0 - g).abs() < 1e-6, "{g}: {v0}");
            let rgb = rgb_under_d65(|l| s.eval(l));
            assert!(close(rgb, [g; 3], 1e-3, 1e-4), "{g}: {rgb:?}");
        }
        // Bounded in [0, 1] everywhere, including the gamut's boundary.
        for rgb in interior_grid(5).into_iter().chain([
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.999, 0.0],
        ]) {
            let s = RgbReflectance::new(rgb);
            for l in 300..900 {
                let v = s.eval(l as f32);
                assert!((0.0..=1.0).contains(&v), "{rgb:?} at {l}: {v}");
            }
        }
    }

    #[test]
    fn clamping_is_reported() {
        let (a, c) = RgbReflectance::new_checked([0.2, 0.5, 0.7]);
        assert!(!c);
        let (b, c) = RgbReflectance::new_checked([-0.1, 0.5, 0.7]);
        assert!(c);
        assert_eq!(b, RgbReflectance::new([0.0, 0.5, 0.7]));
        assert_ne!(a, b);
        assert!(RgbReflectance::new_checked([0.2, 1.5, 0.7]).1);
        assert!(RgbReflectance::new_checked([f32::NAN, 0.5, 0.7]).1);
        assert!(!RgbUnbounded::new_checked([0.2, 15.0, 0.7]).1);
        assert!(RgbUnbounded::new_checked([0.2, -15.0, 0.7]).1);
        assert!(RgbIlluminant::new_checked([-1.0, 1.0, 1.0]).1);
        assert!(!RgbIlluminant::new_checked([10.0, 1.0, 1.0]).1);
        assert_eq!(RgbIlluminant::new([0.0; 3]).eval(500.0), 0.0);
    }

    #[test]
    fn illuminants_round_trip() {
        // White is exactly D65_n.
        let w = RgbIlluminant::new([1.0; 3]);
        for l in (360..=830).step_by(5) {
            let l = l as f32;
            assert!((w.eval(l) - d65_n(l)).abs() <= 1e-6 * d65_n(l), "{l}");
        }
        for rgb in [
            [1.0, 1.0, 1.0],
            [10.0, 10.0, 10.0],
            [1.0, 0.8, 0.6],
            [0.3, 0.5, 1.2],
            [17.0, 12.0, 4.0],
            [0.2, 0.9, 0.1],
            [0.05, 0.05, 0.6],
        ] {
            let s = RgbIlluminant::new(rgb);
            let got = rgb_of(|l| s.eval(l));
            let m = rgb.iter().fold(0.0f32, |a, &b| a.max(b));
            assert!(close(got, rgb, 0.01, 0.005 * m), "{rgb:?} -> {got:?}");
            let u = RgbUnbounded::new(rgb);
            let got = rgb_under_d65(|l| u.eval(l));
            assert!(close(got, rgb, 0.01, 0.005 * m), "{rgb:?} -> {got:?}");
            assert!((u.scale() - 2.0 * m).abs() < 1e-6 * m);
        }
    }

    #[test]
    fn table_matches_exact_fits_at_its_nodes() {
        // At a node the trilinear interpolation returns the node, so the table's lookup of a
        // node colour is the fit of that colour (up to the solver's tolerance).
        let t = srgb_table();
        let res = t.resolution();
        let (zi, yi, xi) = (res / 2, res / 3, res / 4);
        let z = t.z_nodes[zi];
        let rgb = [
            z,
            z * xi as f32 / (res - 1) as f32,
            z * yi as f32 / (res - 1) as f32,
        ];
        let c = t.lookup(rgb);
        let got = table_quadrature().eval(c.map(|v| v as f64)).0;
        for k in 0..3 {
            assert!((got[k] - rgb[k] as f64).abs() < 1e-5, "{got:?} vs {rgb:?}");
        }
    }

    #[test]
    fn lookups_are_deterministic() {
        for rgb in interior_grid(3) {
            let a = RgbReflectance::new(rgb);
            let b = RgbReflectance::new(rgb);
            assert_eq!(
                a.coefficients().map(f32::to_bits),
                b.coefficients().map(f32::to_bits)
            );
            assert_eq!(a.eval(512.3).to_bits(), b.eval(512.3).to_bits());
        }
        let t = RgbToSpectrumTable::build(8);
        let u = RgbToSpectrumTable::build(8);
        assert!(
            t.coeffs
                .iter()
                .zip(&u.coeffs)
                .all(|(a, b)| a.map(f32::to_bits) == b.map(f32::to_bits))
        );
    }

    #[test]
    fn sample3_evaluates_each_lane() {
        let wl = SampledWavelengths::sample_visible(0.37);
        let s = RgbReflectance::new([0.8, 0.3, 0.1]);
        let v = s.sample(&wl);
        for j in 0..3 {
            assert_eq!(v[j], s.eval(wl.lambda[j]));
        }
        assert_eq!(sample3(|l| l, &wl), Spectrum::from_rgb(wl.lambda));
    }
}

/// Measurements behind the choices of [`TABLE_RES`] and [`QUAD_STEP_NM`] (run with
/// `cargo test -p caustica-core --release measure_ -- --ignored --nocapture`).
#[cfg(test)]
mod measurements {
    use super::*;
    use crate::spectral::cie::{spectrum_to_xyz, xyz_to_linear_srgb};
    use std::time::Instant;

    /// One undamped Newton step from `c` toward `rgb`.
    fn polish(q: &Quadrature, rgb: [f32; 3], c: [f32; 3]) -> [f32; 3] {
        let c64 = c.map(|v| v as f64);
        let (got, jac) = q.eval(c64);
        match solve3(jac, [0, 1, 2].map(|k| rgb[k] as f64 - got[k])) {
            Some(d) if d.iter().all(|v| v.is_finite()) => [0, 1, 2].map(|k| (c64[k] + d[k]) as f32),
            _ => c,
        }
    }

    /// CPU time of this process (all threads) in seconds, from Linux's `/proc/self/stat`
    /// (utime + stime, 10 ms ticks), or wall time elsewhere. The machine is shared, so wall
    /// time overstates.
    fn cpu_seconds(wall: Instant) -> f64 {
        std::fs::read_to_string("/proc/self/stat")
            .ok()
            .and_then(|s| {
                // Fields after the command name "(...)": state is field 3, utime 14, stime 15.
                let rest = &s[s.rfind(')')? + 2..];
                let f: Vec<&str> = rest.split_whitespace().collect();
                Some((f[11].parse::<f64>().ok()? + f[12].parse::<f64>().ok()?) / 100.0)
            })
            .unwrap_or_else(|| wall.elapsed().as_secs_f64())
    }

    /// Worst and mean round-trip error over an n³ grid of [0.05, 0.95]³, in units of the
    /// acceptance tolerance max(1 % relative, 0.005 absolute) and as relative error.
    fn round_trip(coeffs: impl Fn([f32; 3]) -> [f32; 3], n: usize) -> (f32, f32, f32) {
        let (mut worst, mut sum, mut worst_rel, mut count) = (0.0f32, 0.0f32, 0.0f32, 0);
        let v = |i: usize| 0.05 + 0.9 * i as f32 / (n - 1) as f32;
        for r in 0..n {
            for g in 0..n {
                for b in 0..n {
                    let rgb = [v(r), v(g), v(b)];
                    let c = coeffs(rgb);
                    let got =
                        xyz_to_linear_srgb(spectrum_to_xyz(|l| eval_coefficients(c, l) * d65_n(l)));
                    for k in 0..3 {
                        let e = (got[k] - rgb[k]).abs();
                        worst = worst.max(e / (0.01 * rgb[k]).max(0.005));
                        worst_rel = worst_rel.max(e / rgb[k]);
                        sum += e / rgb[k];
                        count += 1;
                    }
                }
            }
        }
        (worst, worst_rel, sum / count as f32)
    }

    #[test]
    #[ignore]
    fn measure_table_resolutions() {
        for res in [16, 24, 32, 48, 64] {
            let w0 = Instant::now();
            let c0 = cpu_seconds(w0);
            let (t, evals) = RgbToSpectrumTable::build_counted(res);
            let cpu = cpu_seconds(w0) - c0;
            let wall = w0.elapsed().as_secs_f64();
            let (w, wr, m) = round_trip(|rgb| t.lookup(rgb), 13);
            eprintln!(
                "res {res}: build {:.1} ms CPU ({:.1} ms wall), {:.2} evaluations per node; round trip worst {w:.3} tol, worst rel {:.3} %, mean rel {:.4} %",
                cpu * 1e3,
                wall * 1e3,
                evals as f64 / (3 * res * res * res) as f64,
                wr * 100.0,
                m * 100.0
            );
            let (w, wr, m) = round_trip(|rgb| polish(quadrature(), rgb, t.lookup(rgb)), 13);
            eprintln!(
                "        + one Newton step: worst {w:.3} tol, worst rel {:.3} %, mean rel {:.4} %",
                wr * 100.0,
                m * 100.0
            );
        }
    }

    #[test]
    #[ignore]
    fn measure_evaluation_cost() {
        for (step, simpson) in [(5.0f32, false), (5.0, true)] {
            let q = Quadrature::new(step, simpson);
            let n = 200_000;
            let w0 = Instant::now();
            let c0 = cpu_seconds(w0);
            let mut acc = 0.0;
            for i in 0..n {
                let c = [i as f64 * 1e-6, -1.0, 0.3];
                acc += std::hint::black_box(q.eval(std::hint::black_box(c))).0[1];
            }
            let dt = (cpu_seconds(w0) - c0) / n as f64;
            let w0 = Instant::now();
            let c0 = cpu_seconds(w0);
            for i in 0..n {
                let c = [i as f64 * 1e-6, -1.0, 0.3];
                acc += std::hint::black_box(q.rgb(std::hint::black_box(c)))[1];
            }
            let dt_rgb = (cpu_seconds(w0) - c0) / n as f64;
            eprintln!(
                "eval {step} nm simpson {simpson} ({} nodes): {:.0} ns CPU with Jacobian, {:.0} ns without ({acc:.1})",
                q.t.len(),
                dt * 1e9,
                dt_rgb * 1e9
            );
        }
    }

    #[test]
    #[ignore]
    fn measure_quadrature_steps() {
        // The fit's colour integral at step h against the 1 nm reference, for exact fits.
        for (step, simpson) in [
            (1.0f32, false),
            (2.0, false),
            (5.0, false),
            (10.0, false),
            (5.0, true),
            (10.0, true),
        ] {
            let q = Quadrature::new(step, simpson);
            let (w, wr, m) = round_trip(
                |rgb| newton(&q, rgb.map(|v| v as f64), [0.0; 3], 60, 1e-9).coefficients,
                7,
            );
            eprintln!(
                "quadrature {step} nm simpson {simpson} ({} nodes): exact-fit round trip worst {w:.4} tol, worst rel {:.4} %, mean rel {:.5} %",
                q.t.len(),
                wr * 100.0,
                m * 100.0
            );
        }
    }
}
