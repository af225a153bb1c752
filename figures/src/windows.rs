//! Certified sampling windows as bars on the τ axis: one row per method (or per sensor), the
//! plant file's own window shaded across all rows — the figure of `sporadic compare`.

use super::{FigureError, FigureStyle, color, plot_err, tick_label};
use plotters::prelude::*;
use sporadic_linalg::InputError;
use std::path::Path;

/// One row of [`plot_window_bars`].
#[derive(Debug, Clone, PartialEq)]
pub struct WindowBar {
    /// Row label (method id, with the sensor for round-robin).
    pub label: String,
    /// The certified window `[T1, T2]`, or `None` when nothing was certified.
    pub window: Option<(f64, f64)>,
    /// Text written at the end of the bar (or in the empty row), e.g. `T2 = 0.354` or the
    /// reason nothing was certified.
    pub note: String,
}

/// Draws `rows` as horizontal bars on the sampling-interval axis `[0, x_max]`, first row on
/// top, with `marked` (the plant file's window) shaded across every row.
pub fn plot_window_bars(
    path: &Path,
    title: &str,
    x_label: &str,
    rows: &[WindowBar],
    marked: Option<(f64, f64)>,
    style: FigureStyle,
) -> Result<(), FigureError> {
    if rows.is_empty() {
        return Err(InputError::parameter("rows", 0.0, "at least one row is needed").into());
    }
    let ends = rows
        .iter()
        .filter_map(|r| r.window)
        .chain(marked)
        .flat_map(|(a, b)| [a, b]);
    let mut x_max = 0.0f64;
    for v in ends {
        if !(v.is_finite() && v >= 0.0) {
            return Err(
                InputError::parameter("window end", v, "must be finite and non-negative").into(),
            );
        }
        x_max = x_max.max(v);
    }
    let x_max = if x_max > 0.0 { 1.15 * x_max } else { 1.0 };
    let n = rows.len();
    let height = style.height.max(140 + 60 * n as u32);
    let root = SVGBackend::new(path, (style.width, height)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let font = style.font_size;
    let small = (font * 3 / 4).max(8);
    let longest = rows.iter().map(|r| r.label.len()).max().unwrap_or(1) as u32;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", font))
        .margin(12)
        .x_label_area_size(2 * small + 10)
        .y_label_area_size(longest * small * 6 / 10 + 16)
        .build_cartesian_2d(0.0..x_max, (0..n - 1).into_segmented())
        .map_err(plot_err)?;
    let labels: Vec<&str> = rows.iter().rev().map(|r| r.label.as_str()).collect();
    let row_label = |v: &SegmentValue<usize>| match v {
        SegmentValue::CenterOf(k) => labels.get(*k).map_or(String::new(), |s| s.to_string()),
        _ => String::new(),
    };
    let x_desc = match marked {
        Some((a, b)) => format!("{x_label} (shaded: the plant file's window [{a}, {b}])"),
        None => x_label.to_string(),
    };
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .x_label_formatter(&|v| tick_label(*v, x_max))
        .label_style(("sans-serif", small))
        .axis_desc_style(("sans-serif", small))
        .y_label_formatter(&row_label)
        .y_labels(n)
        .disable_y_mesh()
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(plot_err)?;
    if let Some((a, b)) = marked {
        let band = Rectangle::new(
            [(a, SegmentValue::Exact(0)), (b, SegmentValue::Exact(n))],
            RGBColor(120, 120, 120).mix(0.18).filled(),
        );
        chart.draw_series(std::iter::once(band)).map_err(plot_err)?;
    }
    let text = ("sans-serif", small).into_font();
    for (k, row) in rows.iter().enumerate() {
        let slot = n - 1 - k;
        let col = color(k);
        let note_at = match row.window {
            Some((a, b)) => {
                let mut bar = Rectangle::new(
                    [
                        (a, SegmentValue::Exact(slot)),
                        (b, SegmentValue::Exact(slot + 1)),
                    ],
                    col.mix(0.85).filled(),
                );
                bar.set_margin(8, 8, 0, 0);
                chart.draw_series(std::iter::once(bar)).map_err(plot_err)?;
                b
            }
            None => 0.0,
        };
        chart
            .draw_series(std::iter::once(Text::new(
                format!(" {}", row.note),
                (note_at, SegmentValue::CenterOf(slot)),
                text.clone(),
            )))
            .map_err(plot_err)?;
    }
    root.present().map_err(plot_err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_are_drawn_with_labels_and_notes_and_bad_ends_are_refused() {
        let dir = std::env::temp_dir().join(format!("sporadic-bars-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bars.svg");
        let rows = vec![
            WindowBar {
                label: "ferrante2016".into(),
                window: Some((0.02, 0.354)),
                note: "T2 = 0.354".into(),
            },
            WindowBar {
                label: "andrieu2014".into(),
                window: None,
                note: "not applicable".into(),
            },
        ];
        plot_window_bars(
            &path,
            "certified windows",
            "sampling interval [s]",
            &rows,
            Some((0.02, 0.05)),
            FigureStyle::default(),
        )
        .unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        for needle in [
            "ferrante2016",
            "andrieu2014",
            "T2 = 0.354",
            "not applicable",
        ] {
            assert!(svg.contains(needle), "{needle} missing");
        }
        let bad = [WindowBar {
            window: Some((0.1, f64::NAN)),
            ..rows[0].clone()
        }];
        assert!(plot_window_bars(&path, "t", "x", &bad, None, FigureStyle::default()).is_err());
        assert!(plot_window_bars(&path, "t", "x", &[], None, FigureStyle::default()).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
