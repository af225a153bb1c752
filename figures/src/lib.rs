//! SVG figures of hybrid-time signals in one consistent style (title, axis labels, legend), drawn with `plotters`.
//!
//! Every function takes the data and an output path and returns `Result`. Signals recorded on a hybrid
//! time domain are given as `(t, j, values)`: flows (runs of equal `j`) are drawn as solid lines, jumps
//! (consecutive samples where `j` increments at the same `t`) as dotted segments, and jump instants as
//! light vertical lines — the projection onto ordinary time used in the figures of Ferrante et al. (2016,
//! Fig. 1) and in HyEQ's `plotHybrid`. Non-finite values are rejected.

mod windows;

pub use windows::{WindowBar, plot_window_bars};

use sporadic_linalg::InputError;
use std::ops::Range;
use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

/// Why a figure could not be drawn.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FigureError {
    /// The data to plot is empty, non-finite or of mismatched lengths.
    #[error(transparent)]
    Input(#[from] InputError),
    /// The plotting backend failed (e.g. the file could not be written).
    #[error("plotting failed: {0}")]
    Plot(String),
}

/// Size and font of a figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FigureStyle {
    /// Width in pixels (per figure, all panels together).
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Font size of the title; labels use 3/4 of it.
    pub font_size: u32,
}

impl Default for FigureStyle {
    fn default() -> Self {
        Self {
            width: 800,
            height: 500,
            font_size: 20,
        }
    }
}

/// Title, axis labels and scale of a plot.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotSpec {
    /// Title.
    pub title: String,
    /// Label of the horizontal axis.
    pub x_label: String,
    /// Label of the vertical axis.
    pub y_label: String,
    /// Logarithmic vertical axis (non-positive values are drawn at the bottom of the axis).
    pub log_y: bool,
    /// Size and font.
    pub style: FigureStyle,
}

impl PlotSpec {
    /// A linear-scale plot with the default style.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.to_owned(),
            x_label: x_label.to_owned(),
            y_label: y_label.to_owned(),
            log_y: false,
            style: FigureStyle::default(),
        }
    }

    /// Switches to a logarithmic vertical axis.
    pub fn log_y(mut self) -> Self {
        self.log_y = true;
        self
    }
}

/// A named curve `y(x)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Series<'a> {
    /// Legend entry.
    pub label: &'a str,
    /// Abscissae.
    pub x: &'a [f64],
    /// Ordinates.
    pub y: &'a [f64],
}

/// The ten colours of the "tab10" palette (matplotlib's default cycle).
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];
const JUMP_MARK: RGBColor = RGBColor(190, 190, 190);

fn color(k: usize) -> RGBColor {
    PALETTE[k % PALETTE.len()]
}

/// A set of polylines.
type Polylines = Vec<Vec<(f64, f64)>>;

enum LayerKind {
    /// Solid polylines (one per segment).
    Line,
    /// Dashed polylines.
    Dashed,
    /// Dotted polylines (jumps).
    Dotted,
    /// Filled polygon.
    Band,
    /// Markers.
    Points,
}

struct Layer {
    kind: LayerKind,
    label: Option<String>,
    color: RGBColor,
    segments: Polylines,
}

struct Panel<'a> {
    spec: &'a PlotSpec,
    title: String,
    x_label: String,
    layers: Vec<Layer>,
    vlines: Vec<f64>,
    hline: Option<f64>,
}

fn plot_err<E: std::fmt::Display>(e: E) -> FigureError {
    FigureError::Plot(e.to_string())
}

fn check_series(what: &str, x: &[f64], y: &[f64]) -> Result<(), FigureError> {
    if x.len() != y.len() {
        return Err(InputError::mismatch(format!("length of {what}"), x.len(), y.len()).into());
    }
    if x.is_empty() {
        return Err(InputError::empty(what).into());
    }
    if !x.iter().chain(y).all(|v| v.is_finite()) {
        return Err(InputError::non_finite(what).into());
    }
    Ok(())
}

fn check_hybrid(t: &[f64], j: &[usize], what: &str, y: &[f64]) -> Result<(), FigureError> {
    if j.len() != t.len() {
        return Err(InputError::mismatch("length of the jump counters", t.len(), j.len()).into());
    }
    check_series(what, t, y)
}

/// Splits hybrid samples into flow polylines and jump segments.
fn hybrid_segments(t: &[f64], j: &[usize], y: &[f64]) -> (Polylines, Polylines) {
    let mut flows = vec![vec![(t[0], y[0])]];
    let mut jumps = Vec::new();
    for i in 1..t.len() {
        if j[i] != j[i - 1] {
            jumps.push(vec![(t[i - 1], y[i - 1]), (t[i], y[i])]);
            flows.push(Vec::new());
        }
        if let Some(f) = flows.last_mut() {
            f.push((t[i], y[i]));
        }
    }
    (flows, jumps)
}

fn jump_instants(t: &[f64], j: &[usize]) -> Vec<f64> {
    (1..t.len())
        .filter(|&i| j[i] != j[i - 1])
        .map(|i| t[i])
        .collect()
}

fn hybrid_layers(label: &str, col: RGBColor, t: &[f64], j: &[usize], y: &[f64]) -> Vec<Layer> {
    let (flows, jumps) = hybrid_segments(t, j, y);
    vec![
        Layer {
            kind: LayerKind::Line,
            label: Some(label.to_owned()),
            color: col,
            segments: flows,
        },
        Layer {
            kind: LayerKind::Dotted,
            label: None,
            color: col,
            segments: jumps,
        },
    ]
}

fn data_range(values: impl Iterator<Item = f64>, log: bool) -> Range<f64> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| !log || *v > 0.0) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return if log { 1e-3..1.0 } else { 0.0..1.0 };
    }
    if log {
        if hi <= lo {
            return lo / 10.0..hi * 10.0;
        }
        return lo / 1.5..hi * 1.5;
    }
    if hi <= lo {
        let pad = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return lo - pad..hi + pad;
    }
    let pad = 0.05 * (hi - lo);
    lo - pad..hi + pad
}

/// The longest tick label the vertical axis leaves room for (in characters) without running into
/// the axis title; [`tick_label`] and [`log_tick_label`] stay within it.
const Y_LABEL_CHARS: u32 = 8;

/// A tick label of a linear axis spanning `span`: at most four significant digits, no float
/// noise (`0.30000000000000004`), no `-0`, scientific notation (`2.5e-4`) for very small or
/// large magnitudes.
pub(crate) fn tick_label(v: f64, span: f64) -> String {
    if !v.is_finite() {
        return String::new();
    }
    // Values within round-off of zero (relative to the axis span) are zero.
    if v == 0.0 || v.abs() <= 1e-9 * span.abs() {
        return "0".into();
    }
    // Round to 4 significant digits; `+ 0.0` turns −0.0 into 0.0.
    let rounded: f64 = format!("{v:.3e}").parse::<f64>().unwrap_or(v) + 0.0;
    let a = rounded.abs();
    if (1e-3..1e5).contains(&a) {
        format!("{rounded}")
    } else {
        scientific(rounded)
    }
}

/// Whether a label is one a reader would distrust: a run of 9 or more digits (float noise such
/// as `9.999999999999999e-5`) or a negative zero (`-0`, `-0.0`). The tick labels of this
/// crate's figures never produce one; the tests of every figure check their SVG text with it.
pub fn is_distrusted_label(label: &str) -> bool {
    let mut run = 0;
    for ch in label.chars() {
        run = if ch.is_ascii_digit() { run + 1 } else { 0 };
        if run >= 9 {
            return true;
        }
    }
    label
        .trim()
        .strip_prefix('-')
        .is_some_and(|rest| !rest.is_empty() && rest.chars().all(|c| c == '0' || c == '.'))
}

/// A tick label of a logarithmic axis: powers of ten as `1e-5` (plain decimals from `0.001` to
/// `10000`), other values with at most three significant digits.
fn log_tick_label(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return String::new();
    }
    let e = v.log10().round();
    if (v / 10f64.powf(e) - 1.0).abs() < 1e-6 {
        let e = e as i32;
        return if (-3..=4).contains(&e) {
            format!("{}", 10f64.powi(e))
        } else {
            format!("1e{e}")
        };
    }
    let rounded: f64 = format!("{v:.2e}").parse::<f64>().unwrap_or(v);
    if (1e-3..1e5).contains(&rounded) {
        format!("{rounded}")
    } else {
        scientific(rounded)
    }
}

/// `2.5e-4` rather than Rust's `2.5e-4` with trailing zeros or `2.500e-4`.
fn scientific(v: f64) -> String {
    let s = format!("{v:.3e}");
    match s.split_once('e') {
        Some((m, e)) => {
            let m = if m.contains('.') {
                m.trim_end_matches('0').trim_end_matches('.')
            } else {
                m
            };
            format!("{m}e{e}")
        }
        None => s,
    }
}

fn render(path: &Path, style: FigureStyle, panels: &[Panel<'_>]) -> Result<(), FigureError> {
    let root = SVGBackend::new(path, (style.width, style.height)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let areas = root.split_evenly((1, panels.len()));
    for (area, panel) in areas.iter().zip(panels) {
        let xr = data_range(
            panel
                .layers
                .iter()
                .flat_map(|l| l.segments.iter().flatten().map(|p| p.0)),
            false,
        );
        let ys = panel
            .layers
            .iter()
            .flat_map(|l| l.segments.iter().flatten().map(|p| p.1));
        if panel.spec.log_y {
            let yr = data_range(ys, true);
            let floor = yr.start;
            draw_panel(area, panel, style, xr, yr.log_scale(), floor)?;
        } else {
            let yr = data_range(ys.chain(panel.hline), false);
            let floor = yr.start;
            draw_panel(area, panel, style, xr, yr, floor)?;
        }
    }
    root.present().map_err(plot_err)
}

fn draw_panel<DB, Y>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel<'_>,
    style: FigureStyle,
    xr: Range<f64>,
    y_spec: Y,
    y_floor: f64,
) -> Result<(), FigureError>
where
    DB: DrawingBackend,
    Y: AsRangedCoord<Value = f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let font = style.font_size;
    let small = (font * 3 / 4).max(8);
    let (x0, x1) = (xr.start, xr.end);
    let x_step = (x1 - x0).abs();
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", font))
        .margin(12)
        .x_label_area_size(2 * small + 14)
        .y_label_area_size(Y_LABEL_CHARS * small * 3 / 5 + 2 * small + 10)
        .build_cartesian_2d(xr, y_spec)
        .map_err(plot_err)?;
    let y_span = {
        let r = chart.y_range();
        (r.end - r.start).abs()
    };
    let log_y = panel.spec.log_y;
    let x_fmt = |v: &f64| tick_label(*v, x_step);
    let y_fmt = move |v: &f64| {
        if log_y {
            log_tick_label(*v)
        } else {
            tick_label(*v, y_span)
        }
    };
    chart
        .configure_mesh()
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.spec.y_label.as_str())
        .label_style(("sans-serif", small))
        .axis_desc_style(("sans-serif", small))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(plot_err)?;
    let y_ends = {
        let r = chart.y_range();
        (r.start, r.end)
    };
    let fix = |p: &(f64, f64)| (p.0, p.1.max(y_floor));
    if !panel.vlines.is_empty() {
        chart
            .draw_series(
                panel
                    .vlines
                    .iter()
                    .map(|&t| PathElement::new(vec![(t, y_ends.0), (t, y_ends.1)], JUMP_MARK)),
            )
            .map_err(plot_err)?;
    }
    if let Some(h) = panel.hline {
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(x0, h), (x1, h)],
                BLACK.mix(0.6),
            )))
            .map_err(plot_err)?;
    }
    for layer in &panel.layers {
        let col = layer.color;
        let mut labelled = false;
        for seg in layer.segments.iter().filter(|s| !s.is_empty()) {
            let pts: Vec<(f64, f64)> = seg.iter().map(fix).collect();
            let anno = match layer.kind {
                LayerKind::Line => chart.draw_series(LineSeries::new(pts, col.stroke_width(2))),
                LayerKind::Dashed => {
                    chart.draw_series(DashedLineSeries::new(pts, 8, 5, col.stroke_width(2)))
                }
                LayerKind::Dotted => {
                    chart.draw_series(DashedLineSeries::new(pts, 2, 3, col.stroke_width(1)))
                }
                LayerKind::Band => {
                    chart.draw_series(std::iter::once(Polygon::new(pts, col.mix(0.2).filled())))
                }
                LayerKind::Points => {
                    chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 3, col.filled())))
                }
            }
            .map_err(plot_err)?;
            if let (Some(label), false) = (&layer.label, labelled) {
                labelled = true;
                anno.label(label.as_str()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(2))
                });
            }
        }
    }
    if panel.layers.iter().any(|l| l.label.is_some()) {
        chart
            .configure_series_labels()
            .label_font(("sans-serif", small))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.5))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(plot_err)?;
    }
    Ok(())
}

fn panel<'a>(spec: &'a PlotSpec, layers: Vec<Layer>, vlines: Vec<f64>) -> Panel<'a> {
    Panel {
        spec,
        title: spec.title.clone(),
        x_label: spec.x_label.clone(),
        layers,
        vlines,
        hline: None,
    }
}

/// Estimation-error norm versus ordinary time, with the jump instants marked and an optional bound
/// (e.g. the Theorem 1 bound `κ e^{−γ(t+j)/2}‖ε0‖` of Ferrante et al.), drawn dashed.
pub fn plot_error_norm(
    path: impl AsRef<Path>,
    spec: &PlotSpec,
    t: &[f64],
    j: &[usize],
    norm: &[f64],
    bound: Option<Series<'_>>,
) -> Result<(), FigureError> {
    check_hybrid(t, j, "error norm", norm)?;
    let mut layers = hybrid_layers("error norm", color(0), t, j, norm);
    if let Some(b) = bound {
        check_series(b.label, b.x, b.y)?;
        let pts = b.x.iter().copied().zip(b.y.iter().copied()).collect();
        layers.push(Layer {
            kind: LayerKind::Dashed,
            label: Some(b.label.to_owned()),
            color: color(3),
            segments: vec![pts],
        });
    }
    render(
        path.as_ref(),
        spec.style,
        &[panel(spec, layers, jump_instants(t, j))],
    )
}

/// Several signals (e.g. the error components) versus ordinary time, jump instants marked.
pub fn plot_components(
    path: impl AsRef<Path>,
    spec: &PlotSpec,
    t: &[f64],
    j: &[usize],
    components: &[(&str, &[f64])],
) -> Result<(), FigureError> {
    if components.is_empty() {
        return Err(InputError::empty("components to plot").into());
    }
    let mut layers = Vec::new();
    for (k, (label, y)) in components.iter().enumerate() {
        check_hybrid(t, j, label, y)?;
        layers.extend(hybrid_layers(label, color(k), t, j, y));
    }
    render(
        path.as_ref(),
        spec.style,
        &[panel(spec, layers, jump_instants(t, j))],
    )
}

/// Interval-observer bounds `x̲ <= x <= x̄` of one state component: a shaded band between the bounds, the
/// bounds themselves and the true state (Rabehi et al., Fig. 1–2).
pub fn plot_interval_bounds(
    path: impl AsRef<Path>,
    spec: &PlotSpec,
    t: &[f64],
    j: &[usize],
    lower: &[f64],
    upper: &[f64],
    truth: &[f64],
) -> Result<(), FigureError> {
    check_hybrid(t, j, "lower bound", lower)?;
    check_hybrid(t, j, "upper bound", upper)?;
    check_hybrid(t, j, "true state", truth)?;
    let (lo_flows, _) = hybrid_segments(t, j, lower);
    let (hi_flows, _) = hybrid_segments(t, j, upper);
    let bands = lo_flows
        .iter()
        .zip(&hi_flows)
        .map(|(lo, hi)| lo.iter().copied().chain(hi.iter().rev().copied()).collect())
        .collect();
    let mut layers = vec![Layer {
        kind: LayerKind::Band,
        label: None,
        color: color(0),
        segments: bands,
    }];
    layers.extend(hybrid_layers("lower bound", color(0), t, j, lower));
    layers.extend(hybrid_layers("upper bound", color(3), t, j, upper));
    layers.extend(hybrid_layers("true state", BLACK, t, j, truth));
    render(
        path.as_ref(),
        spec.style,
        &[panel(spec, layers, jump_instants(t, j))],
    )
}

/// Curves versus a parameter, e.g. `λ_min(Ξ_σ(τ))` or `λ_max` of an LMI versus the sampling interval
/// `τ` (Sferlazza et al., Fig. 3), with the zero level drawn as a reference line.
pub fn plot_eigen_curves(
    path: impl AsRef<Path>,
    spec: &PlotSpec,
    curves: &[Series<'_>],
) -> Result<(), FigureError> {
    if curves.is_empty() {
        return Err(InputError::empty("curves to plot").into());
    }
    let mut layers = Vec::new();
    for (k, c) in curves.iter().enumerate() {
        check_series(c.label, c.x, c.y)?;
        let pts = c.x.iter().copied().zip(c.y.iter().copied()).collect();
        layers.push(Layer {
            kind: LayerKind::Line,
            label: Some(c.label.to_owned()),
            color: color(k),
            segments: vec![pts],
        });
    }
    let mut p = panel(spec, layers, Vec::new());
    if !spec.log_y {
        p.hline = Some(0.0);
    }
    render(path.as_ref(), spec.style, &[p])
}

/// A hybrid arc in two panels: projected onto ordinary time `t` (left) and onto the jump counter `j`
/// (right, each flow interval collapses onto a vertical segment at its `j`, jumps are the dotted
/// diagonals), as in Ferrante et al. (2016), Fig. 2.
pub fn plot_hybrid_time(
    path: impl AsRef<Path>,
    spec: &PlotSpec,
    t: &[f64],
    j: &[usize],
    values: &[(&str, &[f64])],
) -> Result<(), FigureError> {
    if values.is_empty() {
        return Err(InputError::empty("signals to plot").into());
    }
    let jf: Vec<f64> = j.iter().map(|&v| v as f64).collect();
    let mut left = Vec::new();
    let mut right = Vec::new();
    for (k, (label, y)) in values.iter().enumerate() {
        check_hybrid(t, j, label, y)?;
        left.extend(hybrid_layers(label, color(k), t, j, y));
        let (flows, jumps) = hybrid_segments(&jf, j, y);
        right.push(Layer {
            kind: LayerKind::Line,
            label: Some((*label).to_owned()),
            color: color(k),
            segments: flows,
        });
        right.push(Layer {
            kind: LayerKind::Dotted,
            label: None,
            color: color(k),
            segments: jumps,
        });
        let post_jump = (0..t.len())
            .filter(|&i| i == 0 || j[i] != j[i - 1])
            .map(|i| (jf[i], y[i]))
            .collect();
        right.push(Layer {
            kind: LayerKind::Points,
            label: None,
            color: color(k),
            segments: vec![post_jump],
        });
    }
    let mut lp = panel(spec, left, jump_instants(t, j));
    lp.title = format!("{} (vs t)", spec.title);
    let mut rp = panel(spec, right, Vec::new());
    rp.title = format!("{} (vs j)", spec.title);
    rp.x_label = "jumps j".to_owned();
    let style = FigureStyle {
        width: spec.style.width.max(2 * spec.style.height),
        ..spec.style
    };
    render(path.as_ref(), style, &[lp, rp])
}

#[cfg(test)]
mod tests {
    use super::{log_tick_label, tick_label};

    #[test]
    fn tick_labels_are_short_and_never_negative_zero() {
        assert_eq!(tick_label(-0.0, 1.0), "0");
        assert_eq!(tick_label(-1e-17, 1.0), "0");
        assert_eq!(tick_label(0.30000000000000004, 1.0), "0.3");
        assert_eq!(tick_label(-0.5, 1.0), "-0.5");
        assert_eq!(tick_label(2.5e-4, 1e-3), "2.5e-4");
        assert_eq!(tick_label(123456.0, 1e6), "1.235e5");
        // Float noise of 1e-4 and 1e-5 as plotters computes them.
        assert_eq!(log_tick_label(9.999999999999999e-5), "1e-4");
        assert_eq!(log_tick_label(9.999999999999999e-6), "1e-5");
        assert_eq!(log_tick_label(0.01), "0.01");
        assert_eq!(log_tick_label(1000.0), "1000");
        assert_eq!(log_tick_label(2e-7), "2e-7");
        for v in [1e-12, 3.3e-9, 0.07, 5.0, 1e4, 2e6] {
            assert!(
                log_tick_label(v).len() <= super::Y_LABEL_CHARS as usize,
                "{v}"
            );
            assert!(
                tick_label(-v, v).len() <= super::Y_LABEL_CHARS as usize,
                "{v}"
            );
        }
    }
}
