//! The demo's figure, drawn with `plotters` (SVG backend): stacked panels over a shared time
//! axis with round tick values, the phases of the script shaded and labelled across every
//! panel, and a band with the drive's state (from the statusword) at the bottom.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One curve: a name, a colour and its y values (one per x sample; NaN leaves a gap).
pub struct Series<'a> {
    /// Shown in the legend.
    pub name: &'a str,
    /// The colour.
    pub colour: RGBColor,
    /// The values, one per sample.
    pub values: &'a [f64],
    /// Drawn dashed (e.g. the commanded value).
    pub dashed: bool,
}

/// One panel: a title, a y-axis label and its series.
pub struct Panel<'a> {
    /// Above the panel, left.
    pub title: &'a str,
    /// Beside the y axis.
    pub unit: &'a str,
    /// The curves.
    pub series: Vec<Series<'a>>,
    /// Relative height.
    pub weight: u32,
}

/// A labelled interval of x: a phase of the script or a state of the drive.
pub struct Span<'a> {
    /// Start, x units.
    pub from: f64,
    /// End, x units.
    pub to: f64,
    /// The label.
    pub label: &'a str,
    /// The fill.
    pub colour: RGBColor,
}

/// The whole figure.
pub struct Figure<'a> {
    /// Above everything.
    pub title: &'a str,
    /// The x values.
    pub x: &'a [f64],
    /// The x axis label.
    pub x_label: &'a str,
    /// The panels, top to bottom.
    pub panels: Vec<Panel<'a>>,
    /// Shaded behind every panel, labelled in the first.
    pub phases: Vec<Span<'a>>,
    /// The state band under the panels.
    pub states: Vec<Span<'a>>,
}

const WIDTH: u32 = 1200;
const PANEL_UNIT: u32 = 120;
const TITLE: u32 = 50;
const BAND: u32 = 70;
const X_AXIS: u32 = 50;
const LEFT: u32 = 95;
const RIGHT: u32 = 30;

/// The SVG document of `figure`.
pub fn svg(figure: &Figure<'_>) -> Result<String, String> {
    let weights: u32 = figure.panels.iter().map(|p| p.weight).sum();
    let height = TITLE + weights * PANEL_UNIT + BAND + X_AXIS;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (WIDTH, height)).into_drawing_area();
        draw(&root, figure, height).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

type Result2 = Result<(), Box<dyn std::error::Error>>;

fn draw(root: &DrawingArea<SVGBackend<'_>, Shift>, figure: &Figure<'_>, height: u32) -> Result2 {
    root.fill(&WHITE)?;
    let (title, rest) = root.split_vertically(TITLE);
    title.draw(&Text::new(
        figure.title,
        (LEFT as i32, 18),
        ("sans-serif", 20).into_font().style(FontStyle::Bold),
    ))?;
    let x_range = range(figure.x.iter().copied(), false);
    let mut area = rest;
    for (i, panel) in figure.panels.iter().enumerate() {
        let (top, below) = area.split_vertically(panel.weight * PANEL_UNIT);
        draw_panel(&top, figure, panel, x_range, i == 0)?;
        area = below;
    }
    let _ = height;
    draw_band(&area, figure, x_range)?;
    Ok(())
}

fn draw_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    figure: &Figure<'_>,
    panel: &Panel<'_>,
    x_range: (f64, f64),
    first: bool,
) -> Result2 {
    let y_range = range(
        panel.series.iter().flat_map(|s| s.values.iter().copied()),
        true,
    );
    let mut chart = ChartBuilder::on(area)
        .margin_left(10)
        .margin_right(RIGHT)
        .margin_top(if first { 40 } else { 8 })
        .margin_bottom(4)
        .y_label_area_size(LEFT - 10)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)?;
    chart
        .configure_mesh()
        .x_labels(12)
        .y_labels(6)
        .x_label_formatter(&|_| String::new())
        .y_label_formatter(&|v| grouped(*v))
        .y_desc(format!("{} ({})", panel.title, panel.unit))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .axis_desc_style(("sans-serif", 13))
        .label_style(("sans-serif", 12))
        .draw()?;
    for phase in &figure.phases {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(phase.from, y_range.0), (phase.to, y_range.1)],
            phase.colour.mix(0.35).filled(),
        )))?;
    }
    if first {
        let base = area.get_base_pixel();
        let mut last_end = i32::MIN;
        let mut row = 0;
        for phase in &figure.phases {
            let middle = (phase.from + phase.to) / 2.0;
            let at = chart.backend_coord(&(middle, y_range.1));
            let half = 4 * phase.label.len() as i32;
            // Two rows when neighbouring labels would overlap.
            row = if at.0 - half < last_end { 1 - row } else { 0 };
            last_end = at.0 + half;
            area.draw(&Text::new(
                phase.label,
                (at.0 - base.0, at.1 - base.1 - 4 - 15 * row),
                ("sans-serif", 13)
                    .into_font()
                    .style(FontStyle::Bold)
                    .color(&RGBColor(60, 60, 60))
                    .pos(Pos::new(HPos::Center, VPos::Bottom)),
            ))?;
        }
    }
    for series in &panel.series {
        let style = ShapeStyle::from(&series.colour).stroke_width(2);
        for (n, run) in finite_runs(figure.x, series.values).into_iter().enumerate() {
            let drawn = if series.dashed {
                chart.draw_series(DashedLineSeries::new(run, 6, 4, style))?
            } else {
                chart.draw_series(LineSeries::new(run, style))?
            };
            // One legend entry per series, not per segment.
            if n == 0 {
                drawn.label(series.name).legend(legend(series.colour));
            }
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(190, 190, 190))
        .label_font(("sans-serif", 12))
        .draw()?;
    Ok(())
}

/// The state band with the x axis under it.
fn draw_band(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    figure: &Figure<'_>,
    x_range: (f64, f64),
) -> Result2 {
    let mut chart = ChartBuilder::on(area)
        .margin_left(10)
        .margin_right(RIGHT)
        .margin_top(26)
        .x_label_area_size(X_AXIS - 6)
        .y_label_area_size(LEFT - 10)
        .build_cartesian_2d(x_range.0..x_range.1, 0.0..1.0)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .disable_y_axis()
        .x_labels(12)
        .x_label_formatter(&|v| grouped(*v))
        .x_desc(figure.x_label)
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .axis_desc_style(("sans-serif", 13))
        .label_style(("sans-serif", 12))
        .draw()?;
    let width = x_range.1 - x_range.0;
    for state in &figure.states {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(state.from, 0.0), (state.to, 1.0)],
            state.colour.filled(),
        )))?;
        // Label the state where there is room for it.
        let room = (state.to - state.from) / width * f64::from(WIDTH - LEFT - RIGHT);
        if room > 7.0 * state.label.len() as f64 {
            let at = chart.backend_coord(&((state.from + state.to) / 2.0, 0.5));
            let base = area.get_base_pixel();
            area.draw(&Text::new(
                state.label,
                (at.0 - base.0, at.1 - base.1),
                ("sans-serif", 12)
                    .into_font()
                    .color(&WHITE)
                    .pos(Pos::new(HPos::Center, VPos::Center)),
            ))?;
        }
    }
    let top = chart.backend_coord(&(x_range.0, 1.0));
    let base = area.get_base_pixel();
    let (x, y) = (top.0 - base.0, top.1 - base.1 - 6);
    area.draw(&Text::new(
        "drive state (statusword)",
        (x, y),
        ("sans-serif", 13)
            .into_font()
            .style(FontStyle::Bold)
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Bottom)),
    ))?;
    // A key of the states shown, right of the title.
    let mut key_x = x + 190;
    let mut seen: Vec<&str> = Vec::new();
    for state in &figure.states {
        if seen.contains(&state.label) {
            continue;
        }
        seen.push(state.label);
        area.draw(&Rectangle::new(
            [(key_x, y - 11), (key_x + 12, y - 1)],
            state.colour.filled(),
        ))?;
        area.draw(&Text::new(
            state.label,
            (key_x + 16, y),
            ("sans-serif", 12)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Bottom)),
        ))?;
        key_x += 30 + 7 * state.label.len() as i32;
    }
    Ok(())
}

fn legend(colour: RGBColor) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new([(x, y), (x + 18, y)], colour.stroke_width(2))
}

/// The runs of consecutive finite values of `values` over `x`.
fn finite_runs(x: &[f64], values: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current = Vec::new();
    for (&x, &y) in x.iter().zip(values) {
        if y.is_finite() {
            current.push((x, y));
        } else if !current.is_empty() {
            runs.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        runs.push(current);
    }
    runs
}

/// The smallest and largest finite value (widened by 6 % when `pad`, and when equal).
fn range(values: impl Iterator<Item = f64>, pad: bool) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if (hi - lo).abs() < f64::EPSILON {
        return (lo - 1.0, hi + 1.0);
    }
    let margin = if pad { (hi - lo) * 0.06 } else { 0.0 };
    (lo - margin, hi + margin)
}

/// A tick value with thin groups of three digits: 250 000, −1 500, 0.5.
pub fn grouped(value: f64) -> String {
    if value.fract().abs() > 1e-9 && value.abs() < 100.0 {
        return format!("{value}");
    }
    let n = value.round() as i64;
    let digits = n.unsigned_abs().to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push('\u{2009}');
        }
        out.push(c);
    }
    if n < 0 { format!("−{out}") } else { out }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_grouped() {
        assert_eq!(grouped(250_000.0), "250\u{2009}000");
        assert_eq!(grouped(-1_500.0), "−1\u{2009}500");
        assert_eq!(grouped(0.0), "0");
        assert_eq!(grouped(0.5), "0.5");
    }

    #[test]
    fn gaps_split_the_series() {
        let runs = finite_runs(&[0.0, 1.0, 2.0, 3.0], &[1.0, f64::NAN, 2.0, 3.0]);
        assert_eq!(runs, vec![vec![(0.0, 1.0)], vec![(2.0, 2.0), (3.0, 3.0)]]);
    }

    #[test]
    fn the_figure_is_an_svg_with_its_labels() {
        let x = [0.0, 1.0, 2.0];
        let y = [0.0, 5.0, 10.0];
        let svg = svg(&Figure {
            title: "t",
            x: &x,
            x_label: "time (ms)",
            panels: vec![Panel {
                title: "Position",
                unit: "counts",
                series: vec![Series {
                    name: "actual",
                    colour: BLUE,
                    values: &y,
                    dashed: false,
                }],
                weight: 2,
            }],
            phases: vec![Span {
                from: 0.0,
                to: 1.0,
                label: "homing",
                colour: RED,
            }],
            states: vec![Span {
                from: 0.0,
                to: 2.0,
                label: "operation enabled",
                colour: GREEN,
            }],
        })
        .unwrap();
        assert!(svg.starts_with("<svg"));
        for label in ["Position", "homing", "operation enabled", "time (ms)"] {
            assert!(svg.contains(label), "{label}");
        }
    }
}
