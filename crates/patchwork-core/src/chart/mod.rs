//! Line and scatter charts as SVG text: one or more panels stacked, each
//! with labelled axes, ticks, grid lines and a legend beside it. Used for
//! the design's profile plot and the bench's time-against-error plot.

mod axis;

use std::fmt::Write;

pub use axis::{Axis, Scale};

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mark {
    Line,
    Dashed,
    Dots,
    Squares,
}

/// Points of one kind; `name: None` keeps it out of the legend (a line
/// joining some of another series' dots, say).
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub name: Option<String>,
    pub colour: &'static str,
    pub mark: Mark,
    pub points: Vec<(f64, f64)>,
}

/// One plot area with its axes and series.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    pub title: String,
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Series>,
}

/// Colours that stay apart from each other in print and for the common
/// colour-vision deficiencies (Okabe–Ito, then Tableau's).
pub const COLOURS: [&str; 12] = [
    "#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#000000", "#8c564b",
    "#7f7f7f", "#bcbd22", "#9467bd", "#17becf",
];

const PANEL_HEIGHT: f64 = 260.0;
const PLOT_WIDTH: f64 = 560.0;
const LEFT: f64 = 70.0;
const TOP: f64 = 34.0;
const BOTTOM: f64 = 48.0;
const LEGEND_WIDTH: f64 = 240.0;
const LEGEND_ROW: f64 = 16.0;

/// The panels stacked top to bottom, each with its legend on its right.
pub fn svg(panels: &[Panel]) -> String {
    let width = LEFT + PLOT_WIDTH + 20.0 + LEGEND_WIDTH;
    let heights: Vec<f64> = panels.iter().map(panel_height).collect();
    let height: f64 = heights.iter().sum();
    let mut s = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">"#
    );
    s.push_str(r#"<rect width="100%" height="100%" fill="white"/>"#);
    let mut top = 0.0;
    for (panel, h) in panels.iter().zip(heights) {
        draw_panel(&mut s, panel, top, h);
        top += h;
    }
    s.push_str("</svg>\n");
    s
}

/// A panel is tall enough for its plot and for its legend.
fn panel_height(panel: &Panel) -> f64 {
    let entries = panel.series.iter().filter(|s| s.name.is_some()).count();
    PANEL_HEIGHT.max(TOP + LEGEND_ROW * (entries as f64 + 1.0))
}

fn draw_panel(s: &mut String, panel: &Panel, top: f64, height: f64) {
    let (x0, y0) = (LEFT, top + TOP);
    let (w, h) = (PLOT_WIDTH, height - TOP - BOTTOM);
    let px = |v: f64| x0 + w * panel.x.fraction(v);
    let py = |v: f64| y0 + h * (1.0 - panel.y.fraction(v));
    let _ = write!(
        s,
        r#"<text x="{x0}" y="{:.1}" font-size="14" font-weight="bold">{}</text>"#,
        top + 20.0,
        escape(&panel.title)
    );
    for tick in panel.x.minor_ticks() {
        let x = px(tick);
        let _ = write!(
            s,
            r##"<line x1="{x:.1}" y1="{y0}" x2="{x:.1}" y2="{:.1}" stroke="#f0f0f0"/>"##,
            y0 + h
        );
    }
    for tick in panel.x.ticks() {
        let x = px(tick);
        let _ = write!(
            s,
            r##"<line x1="{x:.1}" y1="{y0}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/><line x1="{x:.1}" y1="{:.1}" x2="{x:.1}" y2="{:.1}" stroke="black"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
            y0 + h,
            y0 + h,
            y0 + h + 5.0,
            y0 + h + 18.0,
            panel.x.tick_label(tick)
        );
    }
    for tick in panel.y.ticks() {
        let y = py(tick);
        let _ = write!(
            s,
            r##"<line x1="{x0}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><line x1="{:.1}" y1="{y:.1}" x2="{x0}" y2="{y:.1}" stroke="black"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
            x0 + w,
            x0 - 5.0,
            x0 - 8.0,
            y + 4.0,
            panel.y.tick_label(tick)
        );
    }
    let _ = write!(
        s,
        r#"<rect x="{x0}" y="{y0}" width="{w}" height="{h:.1}" fill="none" stroke="black"/><text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text><text transform="translate(16 {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        x0 + w / 2.0,
        y0 + h + 38.0,
        escape(&panel.x.label),
        y0 + h / 2.0,
        escape(&panel.y.label)
    );
    for series in &panel.series {
        draw_series(s, series, &px, &py);
    }
    draw_legend(s, &panel.series, x0 + w + 20.0, y0);
}

fn draw_series(s: &mut String, series: &Series, px: &dyn Fn(f64) -> f64, py: &dyn Fn(f64) -> f64) {
    let finite = series
        .points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    let colour = series.colour;
    match series.mark {
        Mark::Dots | Mark::Squares => {
            for (x, y) in finite {
                marker(s, series.mark, colour, px(*x), py(*y));
            }
        }
        Mark::Line | Mark::Dashed => {
            let points: Vec<String> = finite
                .map(|(x, y)| format!("{:.1},{:.1}", px(*x), py(*y)))
                .collect();
            let dash = match series.mark {
                Mark::Dashed => r#" stroke-dasharray="6 4""#,
                _ => "",
            };
            let _ = write!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="1.8"{dash}/>"#,
                points.join(" ")
            );
        }
    }
}

fn draw_legend(s: &mut String, series: &[Series], x: f64, top: f64) {
    let named = series
        .iter()
        .filter_map(|s| s.name.as_ref().map(|n| (s, n)));
    for (row, (series, name)) in named.enumerate() {
        let y = top + 8.0 + LEGEND_ROW * row as f64;
        let colour = series.colour;
        let _ = match series.mark {
            Mark::Dots | Mark::Squares => {
                marker(s, series.mark, colour, x + 10.0, y);
                Ok(())
            }
            Mark::Line | Mark::Dashed => write!(
                s,
                r#"<line x1="{x:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="{colour}" stroke-width="2"{}/>"#,
                x + 20.0,
                if series.mark == Mark::Dashed {
                    r#" stroke-dasharray="6 4""#
                } else {
                    ""
                }
            ),
        };
        let _ = write!(
            s,
            r#"<text x="{:.1}" y="{:.1}">{}</text>"#,
            x + 26.0,
            y + 4.0,
            escape(name)
        );
    }
}

/// A dot or a square centred on (x, y).
fn marker(s: &mut String, mark: Mark, colour: &str, x: f64, y: f64) {
    let _ = match mark {
        Mark::Squares => write!(
            s,
            r#"<rect x="{:.1}" y="{:.1}" width="8" height="8" fill="{colour}"/>"#,
            x - 4.0,
            y - 4.0
        ),
        _ => write!(
            s,
            r#"<circle cx="{x:.1}" cy="{y:.1}" r="4" fill="{colour}"/>"#
        ),
    };
}

/// Text as SVG character data.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn panel(series: Vec<Series>) -> Panel {
        Panel {
            title: "a <title> & more".into(),
            x: Axis::linear("s (mm)", [0.0, 100.0]),
            y: Axis::linear("κ (1/mm)", [0.0, 0.05]),
            series,
        }
    }

    #[test]
    fn a_chart_names_its_axes_ticks_and_series() {
        let svg = svg(&[panel(vec![
            Series {
                name: Some("target".into()),
                colour: COLOURS[0],
                mark: Mark::Dashed,
                points: vec![(0.0, 0.01), (50.0, f64::NAN), (100.0, 0.04)],
            },
            Series {
                name: None,
                colour: COLOURS[1],
                mark: Mark::Dots,
                points: vec![(10.0, 0.02)],
            },
        ])]);
        for text in [">s (mm)<", ">κ (1/mm)<", ">target<", ">100<", ">0.05<"] {
            assert!(svg.contains(text), "{text} missing");
        }
        assert!(svg.contains("a &lt;title&gt; &amp; more"));
        assert!(!svg.contains("NaN"));
        assert_eq!(
            svg.matches("<circle").count(),
            1,
            "unnamed dots, no legend entry"
        );
        assert_eq!(
            svg.matches("stroke-dasharray").count(),
            2,
            "line and legend"
        );
    }

    #[test]
    fn a_long_legend_makes_its_panel_taller() {
        let many = (0..30)
            .map(|i| Series {
                name: Some(format!("curve {i}")),
                colour: COLOURS[i % COLOURS.len()],
                mark: Mark::Dots,
                points: vec![],
            })
            .collect();
        assert!(panel_height(&panel(many)) > PANEL_HEIGHT);
    }
}
