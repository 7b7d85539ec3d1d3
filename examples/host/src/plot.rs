//! Line charts as standalone SVG: a few series over a shared x axis, in stacked panels, with
//! axes, ticks and a legend. Enough to show commanded against actual motion, no dependencies.

use std::fmt::Write;

/// One curve: a name, a colour and its y values (one per x sample).
pub struct Series<'a> {
    /// Shown in the legend.
    pub name: &'a str,
    /// Any SVG colour.
    pub colour: &'a str,
    /// The values, one per sample.
    pub values: &'a [f64],
    /// Drawn dashed (e.g. the commanded value).
    pub dashed: bool,
}

/// One panel: a title, a y-axis label and its series.
pub struct Panel<'a> {
    /// Above the panel.
    pub title: &'a str,
    /// Beside the y axis.
    pub unit: &'a str,
    /// The curves.
    pub series: Vec<Series<'a>>,
}

const WIDTH: f64 = 900.0;
const PANEL_HEIGHT: f64 = 260.0;
const LEFT: f64 = 90.0;
const RIGHT: f64 = 20.0;
const TOP: f64 = 40.0;
const BOTTOM: f64 = 40.0;

/// The SVG document of `panels` stacked vertically over the x values `x` (labelled `x_label`).
pub fn svg(x: &[f64], x_label: &str, panels: &[Panel<'_>]) -> String {
    let height = PANEL_HEIGHT * panels.len() as f64;
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{height}" viewBox="0 0 {WIDTH} {height}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    for (i, panel) in panels.iter().enumerate() {
        draw_panel(&mut out, i as f64 * PANEL_HEIGHT, x, x_label, panel);
    }
    out.push_str("</svg>\n");
    out
}

/// The smallest and largest finite value, widened when equal.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        (0.0, 1.0)
    } else if (hi - lo).abs() < f64::EPSILON {
        (lo - 1.0, hi + 1.0)
    } else {
        (lo, hi)
    }
}

fn draw_panel(out: &mut String, y0: f64, x: &[f64], x_label: &str, panel: &Panel<'_>) {
    let (x_lo, x_hi) = range(x.iter().copied());
    let (y_lo, y_hi) = range(panel.series.iter().flat_map(|s| s.values.iter().copied()));
    let (plot_w, plot_h) = (WIDTH - LEFT - RIGHT, PANEL_HEIGHT - TOP - BOTTOM);
    let px = |v: f64| LEFT + (v - x_lo) / (x_hi - x_lo) * plot_w;
    let py = |v: f64| y0 + TOP + plot_h - (v - y_lo) / (y_hi - y_lo) * plot_h;
    let _ = writeln!(
        out,
        r#"<text x="{LEFT}" y="{}" font-size="14" font-weight="bold">{}</text>"#,
        y0 + 22.0,
        escape(panel.title)
    );
    let _ = writeln!(
        out,
        r##"<rect x="{LEFT}" y="{}" width="{plot_w}" height="{plot_h}" fill="none" stroke="#888"/>"##,
        y0 + TOP
    );
    for k in 0..=4 {
        let f = f64::from(k) / 4.0;
        let (xv, yv) = (x_lo + f * (x_hi - x_lo), y_lo + f * (y_hi - y_lo));
        let _ = writeln!(
            out,
            r##"<text x="{:.1}" y="{:.1}" text-anchor="middle" fill="#444">{}</text>"##,
            px(xv),
            y0 + PANEL_HEIGHT - BOTTOM + 16.0,
            tick(xv)
        );
        let _ = writeln!(
            out,
            r##"<text x="{:.1}" y="{:.1}" text-anchor="end" fill="#444">{}</text><line x1="{LEFT}" x2="{:.1}" y1="{:.1}" y2="{:.1}" stroke="#eee"/>"##,
            LEFT - 6.0,
            py(yv) + 4.0,
            tick(yv),
            WIDTH - RIGHT,
            py(yv),
            py(yv)
        );
    }
    let _ = writeln!(
        out,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text><text x="14" y="{:.1}" transform="rotate(-90 14 {:.1})" text-anchor="middle">{}</text>"#,
        LEFT + plot_w / 2.0,
        y0 + PANEL_HEIGHT - 6.0,
        escape(x_label),
        y0 + TOP + plot_h / 2.0,
        y0 + TOP + plot_h / 2.0,
        escape(panel.unit)
    );
    for (n, series) in panel.series.iter().enumerate() {
        let points: Vec<String> = x
            .iter()
            .zip(series.values)
            .filter(|(_, v)| v.is_finite())
            .map(|(&xv, &yv)| format!("{:.1},{:.1}", px(xv), py(yv)))
            .collect();
        let dash = if series.dashed {
            r#" stroke-dasharray="6 4""#
        } else {
            ""
        };
        let _ = writeln!(
            out,
            r#"<polyline fill="none" stroke="{}" stroke-width="1.6"{dash} points="{}"/>"#,
            escape(series.colour),
            points.join(" ")
        );
        let lx = LEFT + 10.0 + 190.0 * n as f64;
        let ly = y0 + TOP + 14.0;
        let _ = writeln!(
            out,
            r#"<line x1="{lx}" x2="{}" y1="{ly}" y2="{ly}" stroke="{}" stroke-width="2"{dash}/><text x="{}" y="{}">{}</text>"#,
            lx + 24.0,
            escape(series.colour),
            lx + 30.0,
            ly + 4.0,
            escape(series.name)
        );
    }
}

/// A tick label with no more digits than it needs.
fn tick(v: f64) -> String {
    if v.abs() >= 1000.0 || v == v.trunc() {
        format!("{v:.0}")
    } else {
        format!("{v:.2}")
    }
}

/// `text` with the XML special characters escaped.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_map_the_data_range_onto_the_plot_area() {
        let x = [0.0, 1.0, 2.0];
        let values = [10.0, 20.0, 30.0];
        let doc = svg(
            &x,
            "t",
            &[Panel {
                title: "a < b",
                unit: "u",
                series: vec![Series {
                    name: "s",
                    colour: "red",
                    values: &values,
                    dashed: false,
                }],
            }],
        );
        // First point: left edge, bottom of the plot; last: right edge, top.
        let bottom = TOP + PANEL_HEIGHT - TOP - BOTTOM;
        assert!(
            doc.contains(&format!(r#"points="{LEFT:.1},{bottom:.1} "#)),
            "{doc}"
        );
        assert!(
            doc.contains(&format!(" {:.1},{TOP:.1}\"", WIDTH - RIGHT)),
            "{doc}"
        );
        assert!(doc.contains("a &lt; b"));
        assert!(doc.starts_with("<svg") && doc.ends_with("</svg>\n"));
    }

    #[test]
    fn a_flat_or_empty_series_still_has_a_range() {
        assert_eq!(range([5.0, 5.0].into_iter()), (4.0, 6.0));
        assert_eq!(range([f64::NAN].into_iter()), (0.0, 1.0));
    }
}
