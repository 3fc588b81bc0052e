//! Plots of a parameter sweep: RMSE (left axis) and SSIM (right axis) against the swept
//! parameter, with the RMSE minimum and the SSIM maximum marked and labelled, as in seed 000
//! figs. 6.6–6.7.
//!
//! One drawing goes to an SVG file and to a PNG file (plotters' SVG and bitmap backends). Text is
//! laid out, and rasterised in the PNG, with an embedded subset of DejaVu Sans
//! (`assets/DejaVuSans-subset.ttf`, licence beside it), so no system font is needed; the PNG's
//! glyphs are placed by [`GlyphBackend`], since plotters' own `ab_glyph` text drawing ignores
//! each glyph's side bearing and so spaces letters unevenly. The x axis is
//! linear, logarithmic when the values are all positive and span more than [`LOG_AXIS_RATIO`], or
//! categorical (equally spaced, in the given order) when some value is not a number, e.g. kernel
//! names.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Numeric values that are all positive and whose largest/smallest ratio exceeds this get a
/// logarithmic x axis.
pub const LOG_AXIS_RATIO: f64 = 20.0;
/// Colour of the RMSE curve, its axis title and its legend entry.
pub const RMSE_COLOR: RGBColor = RGBColor(31, 119, 180);
/// Colour of the SSIM curve, its axis title and its legend entry.
pub const SSIM_COLOR: RGBColor = RGBColor(230, 110, 0);
/// Fill of the marker at the RMSE minimum.
pub const RMSE_MARKER_COLOR: RGBColor = RGBColor(200, 30, 30);
/// Fill of the marker at the SSIM maximum.
pub const SSIM_MARKER_COLOR: RGBColor = RGBColor(30, 150, 50);
/// Radius of the optimum markers (pixels).
pub const MARKER_RADIUS: i32 = 8;
/// Smallest picture [`plot_sweep`] draws (pixels).
pub const MIN_SIZE: (u32, u32) = (240, 180);

const FONT: &[u8] = include_bytes!("../assets/DejaVuSans-subset.ttf");
/// The family the embedded font is registered under: SVG viewers fall back to their own
/// sans-serif font for it.
const FAMILY: &str = "sans-serif";
/// Height of the band above the chart holding the title and the legend (pixels).
const HEADER: u32 = 34;

/// Errors of [`plot_sweep`].
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("nothing to plot: the sweep has no points")]
    NoPoints,
    #[error("nothing to plot: no point has a finite RMSE")]
    NoFiniteRmse,
    #[error("a {width}x{height} plot is too small (at least {}x{} pixels)", MIN_SIZE.0, MIN_SIZE.1)]
    TooSmall { width: u32, height: u32 },
    #[error("the embedded plot font cannot be read")]
    Font,
    #[error("cannot draw {path}: {message}")]
    Draw { path: PathBuf, message: String },
    #[error("cannot write {path}")]
    Png {
        path: PathBuf,
        #[source]
        source: image::ImageError,
    },
}

/// One parameter value of a sweep and the errors measured there.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoint {
    /// The parameter value as the user wrote it (a number, or a name such as a kernel).
    pub value: String,
    /// RMSE against the reference (W/m²/sr); non-finite values are not drawn.
    pub rmse: f64,
    /// Mean SSIM against the reference (`None`: not measured, e.g. a region under 11 px wide).
    pub ssim: Option<f64>,
}

/// What to plot: the sweep of one parameter.
#[derive(Clone, Debug)]
pub struct SweepPlot<'a> {
    /// Name of the swept parameter (the x axis title).
    pub parameter: &'a str,
    /// The measurements, in the order the values were given.
    pub points: &'a [SweepPoint],
    /// Picture size in pixels (the SVG's user units are pixels too).
    pub width: u32,
    pub height: u32,
    /// Title above the chart (default: "RMSE and SSIM against PARAMETER").
    pub title: Option<&'a str>,
}

impl<'a> SweepPlot<'a> {
    /// An 800×500 px plot of `points` against `parameter`.
    pub fn new(parameter: &'a str, points: &'a [SweepPoint]) -> Self {
        Self {
            parameter,
            points,
            width: 800,
            height: 500,
            title: None,
        }
    }
}

/// How the x axis places the parameter values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxisKind {
    Linear,
    Logarithmic,
    /// Equally spaced in the given order (some value is not a finite number).
    Categorical,
}

/// The values as numbers, if every one is a finite number.
pub fn numeric_values<S: AsRef<str>>(values: &[S]) -> Option<Vec<f64>> {
    values
        .iter()
        .map(|v| {
            v.as_ref()
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
        })
        .collect()
}

/// Whether numbers call for a logarithmic axis: all positive and spanning more than
/// [`LOG_AXIS_RATIO`].
pub fn wants_log_axis(xs: &[f64]) -> bool {
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    !xs.is_empty() && lo > 0.0 && hi.is_finite() && hi > LOG_AXIS_RATIO * lo
}

/// The x axis for these parameter values.
pub fn axis_kind<S: AsRef<str>>(values: &[S]) -> AxisKind {
    match numeric_values(values) {
        None => AxisKind::Categorical,
        Some(xs) if wants_log_axis(&xs) => AxisKind::Logarithmic,
        Some(_) => AxisKind::Linear,
    }
}

/// Index of the smallest finite value (the first of equals); `None` if there is none.
pub fn argmin(values: &[f64]) -> Option<usize> {
    values
        .iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .fold(None, |best: Option<(usize, f64)>, (i, &v)| match best {
            Some((_, b)) if b <= v => best,
            _ => Some((i, v)),
        })
        .map(|(i, _)| i)
}

/// Index of the largest finite value (the first of equals); `None` if there is none.
pub fn argmax(values: &[Option<f64>]) -> Option<usize> {
    let negated: Vec<f64> = values.iter().map(|v| v.map_or(f64::NAN, |x| -x)).collect();
    argmin(&negated)
}

/// A number in at most four significant digits, switching to scientific notation outside
/// [1e-3, 1e5): `0.01234`, `250`, `1.5e-5`.
pub fn format_number(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.2e}");
    }
    let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Where [`plot_sweep`] drew: pixel positions (x to the right, y down, from the picture's
/// top-left corner; the same in the SVG and the PNG) and the optima.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotLayout {
    pub axis: AxisKind,
    /// Each point's RMSE dot (`None` where the RMSE is not finite), in the order of the points.
    pub rmse: Vec<Option<(i32, i32)>>,
    /// Each point's SSIM dot (`None` where SSIM was not measured).
    pub ssim: Vec<Option<(i32, i32)>>,
    /// Index of the point with the smallest RMSE, and the centre of its marker.
    pub rmse_min: Option<usize>,
    pub rmse_marker: Option<(i32, i32)>,
    /// Index of the point with the largest SSIM, and the centre of its marker.
    pub ssim_max: Option<usize>,
    pub ssim_marker: Option<(i32, i32)>,
}

/// Draws `plot` into an SVG file and a PNG file of `plot.width`×`plot.height` pixels and tells
/// where the points and the optimum markers are.
pub fn plot_sweep(
    plot: &SweepPlot,
    svg_path: &Path,
    png_path: &Path,
) -> Result<PlotLayout, PlotError> {
    if plot.points.is_empty() {
        return Err(PlotError::NoPoints);
    }
    if !plot.points.iter().any(|p| p.rmse.is_finite()) {
        return Err(PlotError::NoFiniteRmse);
    }
    let (w, h) = (plot.width, plot.height);
    if w < MIN_SIZE.0 || h < MIN_SIZE.1 {
        return Err(PlotError::TooSmall {
            width: w,
            height: h,
        });
    }
    register_font()?;
    let draw_err = |path: &Path, e: &dyn std::fmt::Display| PlotError::Draw {
        path: path.to_path_buf(),
        message: e.to_string(),
    };

    let svg_layout = {
        let root = SVGBackend::new(svg_path, (w, h)).into_drawing_area();
        let layout = draw_any(&root, plot).map_err(|e| draw_err(svg_path, &e))?;
        root.present().map_err(|e| draw_err(svg_path, &e))?;
        layout
    };

    let mut buf = vec![0u8; w as usize * h as usize * 3];
    let png_layout = {
        let backend = GlyphBackend::new(BitMapBackend::with_buffer(&mut buf, (w, h)))?;
        let root = backend.into_drawing_area();
        let layout = draw_any(&root, plot).map_err(|e| draw_err(png_path, &e))?;
        root.present().map_err(|e| draw_err(png_path, &e))?;
        layout
    };
    debug_assert_eq!(svg_layout, png_layout);
    let img = image::RgbImage::from_raw(w, h, buf).ok_or_else(|| PlotError::Draw {
        path: png_path.to_path_buf(),
        message: "the bitmap has the wrong size".into(),
    })?;
    img.save_with_format(png_path, image::ImageFormat::Png)
        .map_err(|source| PlotError::Png {
            path: png_path.to_path_buf(),
            source,
        })?;
    Ok(png_layout)
}

fn register_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    if ok { Ok(()) } else { Err(PlotError::Font) }
}

use glyph_backend::GlyphBackend;

mod glyph_backend {
    //! Text drawing for the bitmap backend (a submodule, so that the backend traits' methods do
    //! not shadow plotters' style methods of the same name in the drawing code).

    use super::{FONT, PlotError};
    use plotters::style::text_anchor::{HPos, VPos};
    use plotters_backend::{
        BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend,
        DrawingErrorKind,
    };

    /// A drawing backend that forwards everything to `inner` but draws text itself, with the
    /// embedded font: each glyph at its advance-width caret position with its own side bearing,
    /// anti-aliased, rotated as the style asks. Text boxes are measured as plotters measures them
    /// (the sum of advance widths, [`DrawingBackend::estimate_text_size`] is not overridden), so
    /// the layout is the same as with the SVG backend.
    pub(super) struct GlyphBackend<DB> {
        inner: DB,
        font: ab_glyph::FontRef<'static>,
        /// Height of a capital letter in font units (the outline of 'H'; ab_glyph's outline
        /// bounds have y down, so the height comes out negative and is taken absolute).
        cap_height: f32,
    }

    impl<DB: DrawingBackend> GlyphBackend<DB> {
        pub(super) fn new(inner: DB) -> Result<Self, PlotError> {
            use ab_glyph::Font;
            let font = ab_glyph::FontRef::try_from_slice(FONT).map_err(|_| PlotError::Font)?;
            let cap_height = font
                .outline(font.glyph_id('H'))
                .map(|o| o.bounds.height().abs())
                .ok_or(PlotError::Font)?;
            Ok(Self {
                inner,
                font,
                cap_height,
            })
        }
    }

    impl<DB: DrawingBackend> DrawingBackend for GlyphBackend<DB> {
        type ErrorType = DB::ErrorType;

        fn get_size(&self) -> (u32, u32) {
            self.inner.get_size()
        }
        fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
            self.inner.ensure_prepared()
        }
        fn present(&mut self) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
            self.inner.present()
        }
        fn draw_pixel(
            &mut self,
            point: BackendCoord,
            color: BackendColor,
        ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
            self.inner.draw_pixel(point, color)
        }
        fn draw_line<S: BackendStyle>(
            &mut self,
            from: BackendCoord,
            to: BackendCoord,
            style: &S,
        ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
            self.inner.draw_line(from, to, style)
        }
        fn draw_rect<S: BackendStyle>(
            &mut self,
            upper_left: BackendCoord,
            bottom_right: BackendCoord,
            style: &S,
            fill: bool,
        ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
            self.inner.draw_rect(upper_left, bottom_right, style, fill)
        }
        fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
            &mut self,
            path: I,
            style: &S,
        ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
            self.inner.draw_path(path, style)
        }
        fn draw_circle<S: BackendStyle>(
            &mut self,
            center: BackendCoord,
            radius: u32,
            style: &S,
            fill: bool,
        ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
            self.inner.draw_circle(center, radius, style, fill)
        }
        fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
            &mut self,
            vert: I,
            style: &S,
        ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
            self.inner.fill_polygon(vert, style)
        }
        fn blit_bitmap(
            &mut self,
            pos: BackendCoord,
            size: (u32, u32),
            src: &[u8],
        ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
            self.inner.blit_bitmap(pos, size, src)
        }

        fn draw_text<TStyle: BackendTextStyle>(
            &mut self,
            text: &str,
            style: &TStyle,
            pos: BackendCoord,
        ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
            use ab_glyph::{Font, ScaleFont};
            let color = style.color();
            if color.alpha == 0.0 {
                return Ok(());
            }
            // The text box and anchor exactly as plotters' default `draw_text` computes them.
            let ((min_x, min_y), (max_x, max_y)) = style
                .layout_box(text)
                .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
            let (width, height) = (max_x - min_x, max_y - min_y);
            let dx = match style.anchor().h_pos {
                HPos::Left => 0,
                HPos::Right => -width,
                HPos::Center => -width / 2,
            };
            let dy = match style.anchor().v_pos {
                VPos::Top => 0,
                VPos::Center => -height / 2,
                VPos::Bottom => -height,
            };
            let scaled = self.font.as_scaled(style.size() as f32);
            // Capitals centred in the box, so that VPos::Center centres them on the anchor.
            let cap = self.cap_height * scaled.scale_factor().vertical;
            let baseline = (height as f32 + cap) / 2.0;
            let trans = style.transform();
            let (w, h) = self.get_size();
            let mut pixels = Vec::new();
            let mut caret = 0.0f32;
            let mut prev = None;
            for c in text.chars() {
                let id = scaled.glyph_id(c);
                if let Some(p) = prev {
                    caret += scaled.kern(p, id);
                }
                let glyph =
                    id.with_scale_and_position(scaled.scale(), ab_glyph::point(caret, baseline));
                if let Some(outline) = self.font.outline_glyph(glyph) {
                    let b = outline.px_bounds();
                    outline.draw(|gx, gy, coverage| {
                        let (x, y) = (b.min.x as i32 + gx as i32, b.min.y as i32 + gy as i32);
                        pixels.push((x, y, coverage));
                    });
                }
                caret += scaled.h_advance(id);
                prev = Some(id);
            }
            for (x, y, coverage) in pixels {
                let (x, y) = trans.transform(x + dx - min_x, y + dy - min_y);
                let (x, y) = (pos.0 + x, pos.1 + y);
                if coverage > 0.0 && x >= 0 && x < w as i32 && y >= 0 && y < h as i32 {
                    self.inner
                        .draw_pixel((x, y), color.mix(f64::from(coverage.min(1.0))))?;
                }
            }
            Ok(())
        }
    }
}

type DrawResult<T, DB> = Result<T, DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// How the x axis is labelled.
enum Ticks {
    /// Plotters' own ticks and labels (linear numbers).
    Auto,
    /// Hand-placed ticks: x position (in the chart's x coordinate), label, major (bold grid
    /// line) or minor.
    Manual(Vec<(f64, String, bool)>),
}

/// Ticks of a logarithmic axis over [10^lo, 10^hi], in log10 units: a grid line at every
/// m·10^k, labels at 1, 2 and 5 ·10^k (only at powers of ten when the range spans more than
/// three decades).
fn log_ticks(lo: f64, hi: f64) -> Vec<(f64, String, bool)> {
    let mut ticks = Vec::new();
    let few = hi - lo <= 3.0;
    for k in lo.floor() as i32..=hi.ceil() as i32 {
        for m in 1..10 {
            let v = f64::from(m) * 10f64.powi(k);
            let x = v.log10();
            if x < lo || x > hi {
                continue;
            }
            let labelled = m == 1 || (few && (m == 2 || m == 5));
            let label = if labelled {
                format_number(v)
            } else {
                String::new()
            };
            ticks.push((x, label, m == 1));
        }
    }
    ticks
}

/// Chooses the x axis and draws. Every axis is linear in the chart's x coordinate: the value,
/// its log10 on a logarithmic axis, or its index for categories.
fn draw_any<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: &SweepPlot,
) -> DrawResult<PlotLayout, DB> {
    let values: Vec<&str> = plot.points.iter().map(|p| p.value.as_str()).collect();
    let axis = axis_kind(&values);
    match (axis, numeric_values(&values)) {
        (AxisKind::Logarithmic, Some(xs)) => {
            let lx: Vec<f64> = xs.iter().map(|x| x.log10()).collect();
            let range = padded(&lx, 0.05, false);
            let ticks = log_ticks(range.start, range.end);
            draw(root, plot, axis, &lx, range, Ticks::Manual(ticks))
        }
        (AxisKind::Linear, Some(xs)) => {
            let range = padded(&xs, 0.05, false);
            draw(root, plot, axis, &xs, range, Ticks::Auto)
        }
        _ => {
            let n = values.len();
            let xs: Vec<f64> = (0..n).map(|i| i as f64).collect();
            let ticks = values
                .iter()
                .enumerate()
                .map(|(i, v)| (i as f64, v.to_string(), true))
                .collect();
            let range = -0.5..n as f64 - 0.5;
            draw(
                root,
                plot,
                AxisKind::Categorical,
                &xs,
                range,
                Ticks::Manual(ticks),
            )
        }
    }
}

/// The range of `v` widened by `pad` of its span on each side (a sensible width when all
/// values are equal); never below 0 when `non_negative` and the values are not.
fn padded(v: &[f64], pad: f64, non_negative: bool) -> Range<f64> {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let span = hi - lo;
    let d = if span > 0.0 {
        span * pad
    } else if hi != 0.0 {
        hi.abs() * 0.1
    } else {
        1.0
    };
    let start = if non_negative && lo >= 0.0 {
        (lo - d).max(0.0)
    } else {
        lo - d
    };
    start..hi + d
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: &SweepPlot,
    axis: AxisKind,
    xs: &[f64],
    x_range: Range<f64>,
    ticks: Ticks,
) -> DrawResult<PlotLayout, DB> {
    let points = plot.points;
    let rmse: Vec<f64> = points.iter().map(|p| p.rmse).collect();
    let ssim: Vec<Option<f64>> = points
        .iter()
        .map(|p| p.ssim.filter(|s| s.is_finite()))
        .collect();
    let finite_rmse: Vec<f64> = rmse.iter().copied().filter(|v| v.is_finite()).collect();
    let finite_ssim: Vec<f64> = ssim.iter().flatten().copied().collect();
    let has_ssim = !finite_ssim.is_empty();
    // Room above and below the curves for the optimum labels.
    let rmse_range = padded(&finite_rmse, 0.15, true);
    let ssim_range = if has_ssim {
        padded(&finite_ssim, 0.15, false)
    } else {
        0.0..1.0
    };
    // Lines join the points in order of x (numbers may be given in any order).
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| xs[a].total_cmp(&xs[b]));

    root.fill(&WHITE)?;
    let (header, body) = root.split_vertically(HEADER);
    let default_title = format!("RMSE and SSIM against {}", plot.parameter);
    let title = plot.title.unwrap_or(&default_title);
    header.draw(&Text::new(
        title.to_string(),
        (12, HEADER as i32 / 2),
        (FAMILY, 18)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center)),
    ))?;
    draw_legend(&header, plot.width as i32, has_ssim)?;

    let mut chart = ChartBuilder::on(&body)
        .margin_left(8)
        .margin_right(8)
        .margin_top(6)
        .margin_bottom(8)
        .x_label_area_size(46)
        .y_label_area_size(80)
        .right_y_label_area_size(if has_ssim { 70 } else { 8 })
        .build_cartesian_2d(x_range.clone(), rmse_range)?
        .set_secondary_coord(x_range, ssim_range);
    let number = |v: &f64| format_number(*v);
    let grid_light = RGBColor(240, 240, 240);
    let grid_bold = RGBColor(215, 215, 215);
    {
        let mut mesh = chart.configure_mesh();
        mesh.x_desc(plot.parameter)
            .y_desc("RMSE (W/m²/sr)")
            .y_labels(8)
            .y_label_formatter(&number)
            .label_style((FAMILY, 13))
            .axis_desc_style((FAMILY, 15).into_font().color(&RMSE_COLOR))
            .max_light_lines(4)
            .light_line_style(grid_light)
            .bold_line_style(grid_bold);
        match ticks {
            Ticks::Auto => {
                mesh.x_labels(8).x_label_formatter(&number);
            }
            Ticks::Manual(_) => {
                mesh.x_labels(0).disable_x_mesh();
            }
        }
        mesh.draw()?;
    }
    if has_ssim {
        chart
            .configure_secondary_axes()
            .y_desc("SSIM")
            .y_labels(8)
            .y_label_formatter(&number)
            .label_style((FAMILY, 13))
            .axis_desc_style((FAMILY, 15).into_font().color(&SSIM_COLOR))
            .draw()?;
    }
    let (area_x, area_y) = chart.plotting_area().get_pixel_range();
    if let Ticks::Manual(ticks) = &ticks {
        let y0 = chart.y_range().start;
        let label_font = (FAMILY, 13)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Top));
        for (x, label, major) in ticks {
            let px = chart.backend_coord(&(*x, y0)).0;
            let grid = if *major { grid_bold } else { grid_light };
            root.draw(&PathElement::new(
                vec![(px, area_y.start), (px, area_y.end - 1)],
                grid.stroke_width(1),
            ))?;
            if !label.is_empty() {
                root.draw(&PathElement::new(
                    vec![(px, area_y.end), (px, area_y.end + 5)],
                    BLACK.stroke_width(1),
                ))?;
                root.draw(&Text::new(
                    label.clone(),
                    (px, area_y.end + 8),
                    label_font.clone(),
                ))?;
            }
        }
    }

    // Categories (e.g. kernels) have no order between them: dots only, no joining lines.
    let joined = axis != AxisKind::Categorical;
    let rmse_line: Vec<(f64, f64)> = order
        .iter()
        .filter(|&&i| rmse[i].is_finite())
        .map(|&i| (xs[i], rmse[i]))
        .collect();
    let ssim_line: Vec<(f64, f64)> = order
        .iter()
        .filter_map(|&i| ssim[i].map(|s| (xs[i], s)))
        .collect();
    if joined {
        chart.draw_series(LineSeries::new(
            rmse_line.iter().copied(),
            RMSE_COLOR.stroke_width(2),
        ))?;
        if has_ssim {
            chart.draw_secondary_series(LineSeries::new(
                ssim_line.iter().copied(),
                SSIM_COLOR.stroke_width(2),
            ))?;
        }
    }
    chart.draw_series(
        rmse_line
            .iter()
            .map(|&p| Circle::new(p, 4, RMSE_COLOR.filled())),
    )?;
    // Square SSIM dots of side 8 px, drawn in pixel space.
    let ssim_curve: Vec<(i32, i32)> = ssim_line
        .iter()
        .map(|p| chart.borrow_secondary().backend_coord(p))
        .collect();
    for &(px, py) in &ssim_curve {
        root.draw(&Rectangle::new(
            [(px - 4, py - 4), (px + 4, py + 4)],
            SSIM_COLOR.filled(),
        ))?;
    }
    let rmse_curve: Vec<(i32, i32)> = rmse_line.iter().map(|p| chart.backend_coord(p)).collect();

    let rmse_px: Vec<Option<(i32, i32)>> = (0..points.len())
        .map(|i| {
            rmse[i]
                .is_finite()
                .then(|| chart.backend_coord(&(xs[i], rmse[i])))
        })
        .collect();
    let ssim_px: Vec<Option<(i32, i32)>> = (0..points.len())
        .map(|i| ssim[i].map(|s| chart.borrow_secondary().backend_coord(&(xs[i], s))))
        .collect();
    let rmse_min = argmin(&rmse);
    let ssim_max = argmax(&ssim);
    let rmse_marker = rmse_min.and_then(|i| rmse_px[i]);
    let ssim_marker = ssim_max.and_then(|i| ssim_px[i]);

    // What a label should not cover: the curves (sampled every 2 px), dots and markers.
    let mut obstacles = Vec::new();
    for curve in [&rmse_curve, &ssim_curve] {
        obstacles.extend(curve.iter().copied());
        if joined {
            for w in curve.windows(2) {
                obstacles.extend(segment_points(w[0], w[1]));
            }
        }
    }
    obstacles.extend(rmse_marker);
    obstacles.extend(ssim_marker);
    let area = (area_x, area_y);
    if let (Some(i), Some(c)) = (rmse_min, rmse_marker) {
        let text = format!(
            "min RMSE {} at {} = {}",
            format_number(rmse[i]),
            plot.parameter,
            points[i].value
        );
        let b = draw_marker(root, c, RMSE_MARKER_COLOR, &text, true, &area, &obstacles)?;
        obstacles.extend(box_points(b));
    }
    if let (Some(i), Some(c)) = (ssim_max, ssim_marker) {
        let text = format!(
            "max SSIM {} at {} = {}",
            format_number(ssim[i].unwrap_or(f64::NAN)),
            plot.parameter,
            points[i].value
        );
        draw_marker(root, c, SSIM_MARKER_COLOR, &text, false, &area, &obstacles)?;
    }
    Ok(PlotLayout {
        axis,
        rmse: rmse_px,
        ssim: ssim_px,
        rmse_min,
        rmse_marker,
        ssim_max,
        ssim_marker,
    })
}

/// Points every 2 px along the segment from `a` to `b`.
fn segment_points(a: (i32, i32), b: (i32, i32)) -> Vec<(i32, i32)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let n = (dx.abs().max(dy.abs()) / 2).max(1);
    (0..=n)
        .map(|k| (a.0 + dx * k / n, a.1 + dy * k / n))
        .collect()
}

/// Points every 4 px over a box (`[x0, y0, x1, y1]`).
fn box_points([x0, y0, x1, y1]: [i32; 4]) -> Vec<(i32, i32)> {
    (y0..=y1)
        .step_by(4)
        .flat_map(|y| (x0..=x1).step_by(4).map(move |x| (x, y)))
        .collect()
}

/// The legend at the right of the header band: a line swatch and name per curve.
fn draw_legend<DB: DrawingBackend>(
    header: &DrawingArea<DB, Shift>,
    width: i32,
    has_ssim: bool,
) -> DrawResult<(), DB> {
    let y = HEADER as i32 / 2;
    let entries = if has_ssim {
        vec![("RMSE (left)", RMSE_COLOR), ("SSIM (right)", SSIM_COLOR)]
    } else {
        vec![("RMSE", RMSE_COLOR)]
    };
    let mut x = width - 12;
    for (name, color) in entries.into_iter().rev() {
        let style = (FAMILY, 14)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Right, VPos::Center));
        let (tw, _) = header.estimate_text_size(name, &style)?;
        header.draw(&Text::new(name.to_string(), (x, y), style))?;
        x -= tw as i32 + 6;
        header.draw(&PathElement::new(
            vec![(x - 22, y), (x, y)],
            color.stroke_width(3),
        ))?;
        x -= 22 + 18;
    }
    Ok(())
}

/// A filled, outlined circle at `c` and a label beside it, at whichever of the four corners
/// around the marker keeps inside the plotting `area` and covers the fewest `obstacles`
/// (ties: above the marker if `above`, else below; toward the middle of the area). Returns the
/// label's box `[x0, y0, x1, y1]`.
fn draw_marker<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    c: (i32, i32),
    fill: RGBColor,
    text: &str,
    above: bool,
    (area_x, area_y): &(Range<i32>, Range<i32>),
    obstacles: &[(i32, i32)],
) -> DrawResult<[i32; 4], DB> {
    root.draw(&Circle::new(c, MARKER_RADIUS, fill.filled()))?;
    root.draw(&Circle::new(c, MARKER_RADIUS, BLACK.stroke_width(1)))?;
    let font = (FAMILY, 14).into_font().color(&fill);
    let (tw, th) = root.estimate_text_size(text, &font)?;
    let (tw, th) = (tw as i32, th as i32);
    let gap = MARKER_RADIUS + 4;
    let inward = c.0 <= (area_x.start + area_x.end) / 2;
    let mut best: Option<(usize, (i32, i32))> = None;
    for up in [above, !above] {
        for right in [inward, !inward] {
            let x = if right { c.0 + gap } else { c.0 - gap - tw };
            let y = if up { c.1 - gap - th } else { c.1 + gap };
            let inside = x - 3 >= area_x.start
                && x + tw + 3 <= area_x.end
                && y - 2 >= area_y.start
                && y + th + 2 <= area_y.end;
            let covered = obstacles
                .iter()
                .filter(|&&(ox, oy)| {
                    ox >= x - 5 && ox <= x + tw + 5 && oy >= y - 4 && oy <= y + th + 4
                })
                .count();
            let score = covered + if inside { 0 } else { 100_000 };
            if best.is_none_or(|(b, _)| score < b) {
                best = Some((score, (x, y)));
            }
        }
    }
    let (x, y) = best.map_or((c.0 + gap, c.1 + gap), |(_, p)| p);
    // Keep the label inside the area even when no corner fits.
    let x = x.clamp(
        area_x.start + 3,
        (area_x.end - tw - 3).max(area_x.start + 3),
    );
    let y = y.clamp(
        area_y.start + 2,
        (area_y.end - th - 2).max(area_y.start + 2),
    );
    // A light box keeps the label legible over grid lines.
    root.draw(&Rectangle::new(
        [(x - 3, y - 2), (x + tw + 3, y + th + 2)],
        WHITE.mix(0.85).filled(),
    ))?;
    root.draw(&Text::new(
        text.to_string(),
        (x, y),
        font.pos(Pos::new(HPos::Left, VPos::Top)),
    ))?;
    Ok([x - 3, y - 2, x + tw + 3, y + th + 2])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn points(values: &[&str], rmse: &[f64], ssim: &[f64]) -> Vec<SweepPoint> {
        values
            .iter()
            .zip(rmse)
            .zip(ssim)
            .map(|((v, &r), &s)| SweepPoint {
                value: v.to_string(),
                rmse: r,
                ssim: Some(s),
            })
            .collect()
    }

    fn tmp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("caustica-plot-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    fn rgb(c: RGBColor) -> [u8; 3] {
        [c.0, c.1, c.2]
    }

    fn pixel(img: &image::RgbImage, (x, y): (i32, i32)) -> [u8; 3] {
        img.get_pixel(x as u32, y as u32).0
    }

    #[test]
    fn log_axis_decision() {
        assert!(!wants_log_axis(&[1.0, 4.0, 16.0]));
        assert!(!wants_log_axis(&[1.0, 20.0]));
        assert!(wants_log_axis(&[1.0, 20.5]));
        assert!(wants_log_axis(&[16.0, 1.0, 4.0, 64.0]));
        assert!(!wants_log_axis(&[0.0, 10.0, 1000.0]));
        assert!(!wants_log_axis(&[-1.0, 100.0]));
        assert!(!wants_log_axis(&[5.0]));
        assert!(!wants_log_axis(&[]));
        assert_eq!(axis_kind(&["1", "4", "16"]), AxisKind::Linear);
        assert_eq!(axis_kind(&["1000", "1e5", "1e6"]), AxisKind::Logarithmic);
        assert_eq!(
            axis_kind(&["uniform", "epanechnikov"]),
            AxisKind::Categorical
        );
        assert_eq!(axis_kind(&["1", "nan"]), AxisKind::Categorical);
        assert_eq!(numeric_values(&[" 2.5", "-1"]), Some(vec![2.5, -1.0]));
    }

    #[test]
    fn optimum_finding() {
        assert_eq!(argmin(&[3.0, 1.0, 2.0, 1.0]), Some(1));
        assert_eq!(argmin(&[f64::NAN, 5.0, f64::INFINITY, 4.0]), Some(3));
        assert_eq!(argmin(&[f64::NAN]), None);
        assert_eq!(argmin(&[]), None);
        assert_eq!(argmax(&[Some(0.5), None, Some(0.9), Some(0.9)]), Some(2));
        assert_eq!(argmax(&[None, Some(f64::NAN)]), None);
        assert_eq!(argmax(&[Some(-0.2), Some(-0.1)]), Some(1));
    }

    #[test]
    fn number_formatting() {
        assert_eq!(format_number(0.0), "0");
        assert_eq!(format_number(0.012345), "0.01235");
        assert_eq!(format_number(250.0), "250");
        assert_eq!(format_number(1.5), "1.5");
        assert_eq!(format_number(12345.0), "12345");
        assert_eq!(format_number(1.5e-5), "1.50e-5");
        assert_eq!(format_number(-0.25), "-0.25");
    }

    #[test]
    fn writes_svg_and_png_of_the_requested_size() {
        let pts = points(&["1", "4", "16"], &[0.3, 0.1, 0.05], &[0.5, 0.7, 0.8]);
        let (svg, png) = (tmp("size.svg"), tmp("size.png"));
        let plot = SweepPlot {
            width: 640,
            height: 400,
            ..SweepPlot::new("spp", &pts)
        };
        plot_sweep(&plot, &svg, &png).unwrap();
        let img = image::open(&png).unwrap();
        assert_eq!((img.width(), img.height()), (640, 400));
        let text = std::fs::read_to_string(&svg).unwrap();
        let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "svg");
        assert_eq!(root.attribute("width"), Some("640"));
        assert_eq!(root.attribute("height"), Some("400"));
        let texts: Vec<String> = doc
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .filter_map(|n| n.text().map(str::to_string))
            .collect();
        for want in [
            "min RMSE 0.05 at spp = 16",
            "max SSIM 0.8 at spp = 16",
            "SSIM",
        ] {
            assert!(
                texts.iter().any(|t| t.contains(want)),
                "no '{want}' in {texts:?}"
            );
        }
        // The PNG has text: dark pixels in the title band.
        let rgb = img.to_rgb8();
        let dark = (0..HEADER)
            .flat_map(|y| (0..640).map(move |x| (x, y)))
            .filter(|&(x, y)| rgb.get_pixel(x, y).0.iter().all(|&c| c < 100))
            .count();
        assert!(dark > 50, "no title text in the PNG ({dark} dark pixels)");
    }

    #[test]
    fn markers_sit_at_the_optima() {
        // RMSE smallest at index 2, SSIM largest at index 3; values out of order.
        let pts = points(
            &["2", "1", "4", "3", "5"],
            &[0.4, 0.5, 0.1, 0.2, 0.3],
            &[0.6, 0.5, 0.7, 0.9, 0.8],
        );
        let (svg, png) = (tmp("optima.svg"), tmp("optima.png"));
        let layout = plot_sweep(&SweepPlot::new("k", &pts), &svg, &png).unwrap();
        assert_eq!(layout.axis, AxisKind::Linear);
        assert_eq!(layout.rmse_min, Some(2));
        assert_eq!(layout.ssim_max, Some(3));
        assert_eq!(layout.rmse_marker, layout.rmse[2]);
        assert_eq!(layout.ssim_marker, layout.ssim[3]);
        // Positions follow the values: x by parameter, y by RMSE (down = smaller).
        let x = |i: usize| layout.rmse[i].unwrap().0;
        assert!(x(1) < x(0) && x(0) < x(3) && x(3) < x(2) && x(2) < x(4));
        assert!((x(0) - x(1) - (x(3) - x(0))).abs() <= 1, "linear spacing");
        assert!(layout.rmse[2].unwrap().1 > layout.rmse[1].unwrap().1);
        // The secondary (SSIM) axis maps x to within a pixel of the primary one.
        assert!((layout.ssim[3].unwrap().0 - x(3)).abs() <= 1);
        let img = image::open(&png).unwrap().to_rgb8();
        let (rm, sm) = (layout.rmse_marker.unwrap(), layout.ssim_marker.unwrap());
        assert_eq!(pixel(&img, rm), rgb(RMSE_MARKER_COLOR));
        assert_eq!(pixel(&img, sm), rgb(SSIM_MARKER_COLOR));
        for i in [0, 1, 4] {
            assert_eq!(pixel(&img, layout.rmse[i].unwrap()), rgb(RMSE_COLOR));
            assert_eq!(pixel(&img, layout.ssim[i].unwrap()), rgb(SSIM_COLOR));
        }
        // The SVG draws the same markers at the same place.
        let text = std::fs::read_to_string(&svg).unwrap();
        let doc = roxmltree::Document::parse(&text).unwrap();
        let hex = |c: RGBColor| format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2);
        for (c, color) in [(rm, RMSE_MARKER_COLOR), (sm, SSIM_MARKER_COLOR)] {
            let found = doc.descendants().any(|n| {
                n.has_tag_name("circle")
                    && n.attribute("fill")
                        .is_some_and(|f| f.eq_ignore_ascii_case(&hex(color)))
                    && n.attribute("cx") == Some(&c.0.to_string())
                    && n.attribute("cy") == Some(&c.1.to_string())
            });
            assert!(found, "no {} marker at {c:?} in the SVG", hex(color));
        }
    }

    #[test]
    fn log_and_categorical_axes_space_points_evenly() {
        let pts = points(
            &["10", "100", "1000", "10000"],
            &[0.4, 0.2, 0.1, 0.3],
            &[0.5, 0.6, 0.9, 0.8],
        );
        let layout = plot_sweep(
            &SweepPlot::new("photons", &pts),
            &tmp("log.svg"),
            &tmp("log.png"),
        )
        .unwrap();
        assert_eq!(layout.axis, AxisKind::Logarithmic);
        let x: Vec<i32> = layout.rmse.iter().map(|p| p.unwrap().0).collect();
        let d = x[1] - x[0];
        assert!(d > 50 && (x[2] - x[1] - d).abs() <= 1 && (x[3] - x[2] - d).abs() <= 1);

        // Kernel names: categories in the given order; SSIM may be missing.
        let mut pts = points(
            &["uniform", "epanechnikov", "cone:1.1"],
            &[0.3, 0.2, 0.25],
            &[0.0; 3],
        );
        for p in &mut pts {
            p.ssim = None;
        }
        let (svg, png) = (tmp("cat.svg"), tmp("cat.png"));
        let layout = plot_sweep(&SweepPlot::new("kernel", &pts), &svg, &png).unwrap();
        assert_eq!(layout.axis, AxisKind::Categorical);
        assert_eq!((layout.rmse_min, layout.ssim_max), (Some(1), None));
        let x: Vec<i32> = layout.rmse.iter().map(|p| p.unwrap().0).collect();
        assert!(x[0] < x[1] && (x[2] - x[1] - (x[1] - x[0])).abs() <= 1);
        let text = std::fs::read_to_string(&svg).unwrap();
        let doc = roxmltree::Document::parse(&text).unwrap();
        let labels: Vec<&str> = doc
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .filter_map(|n| n.text().map(str::trim))
            .collect();
        for want in ["uniform", "epanechnikov", "cone:1.1"] {
            assert!(labels.contains(&want), "no x label '{want}' in {labels:?}");
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let (svg, png) = (tmp("bad.svg"), tmp("bad.png"));
        assert!(matches!(
            plot_sweep(&SweepPlot::new("k", &[]), &svg, &png),
            Err(PlotError::NoPoints)
        ));
        let pts = points(&["1"], &[f64::NAN], &[0.5]);
        assert!(matches!(
            plot_sweep(&SweepPlot::new("k", &pts), &svg, &png),
            Err(PlotError::NoFiniteRmse)
        ));
        let pts = points(&["1"], &[0.1], &[0.5]);
        let tiny = SweepPlot {
            width: 10,
            ..SweepPlot::new("k", &pts)
        };
        assert!(matches!(
            plot_sweep(&tiny, &svg, &png),
            Err(PlotError::TooSmall { .. })
        ));
        // A single point still plots.
        let layout = plot_sweep(&SweepPlot::new("k", &pts), &svg, &png).unwrap();
        assert_eq!((layout.rmse_min, layout.ssim_max), (Some(0), Some(0)));
        let missing = tmp("no-such-dir").join("x").join("p.png");
        assert!(matches!(
            plot_sweep(&SweepPlot::new("k", &pts), &svg, &missing),
            Err(PlotError::Png { .. })
        ));
    }
}
