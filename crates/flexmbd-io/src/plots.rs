//! Plots as PNG and SVG with `plotters` (docs/visualisation.md): singular value spectrum of
//! Dcc, force–stroke, support stiffness vs stroke and frequency vs stroke.
//!
//! Text is drawn with DejaVu Sans (assets/fonts/, Bitstream Vera licence), compiled into the
//! binary and registered with plotters as `sans-serif`, so no system font is needed.

use plotters::prelude::*;
use std::path::{Path, PathBuf};

static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// Register the shipped font once.
fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
            .unwrap_or_else(|_| panic!("assets/fonts/DejaVuSans.ttf is not a valid font"));
    });
}

/// A tick label: plain for moderate magnitudes, else scientific, at most 4 significant digits.
fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        let s = format!("{:.*}", (3 - a.log10().floor() as i32).max(0) as usize, v);
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{v:.2e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.')
        } else {
            m
        };
        format!("{m}e{e}")
    }
}

/// One curve.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// (x, y) points; non-finite points (and y ≤ 0 on a log axis) are left out.
    pub points: Vec<(f64, f64)>,
}

/// A line plot.
#[derive(Clone, Debug)]
pub struct Plot {
    /// Title.
    pub title: String,
    /// x axis label (with unit).
    pub x_label: String,
    /// y axis label (with unit).
    pub y_label: String,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// Curves.
    pub series: Vec<Series>,
    /// Horizontal lines (label, y), e.g. a threshold.
    pub hlines: Vec<(String, f64)>,
    /// Draw a marker at every point.
    pub markers: bool,
    /// Join the points of a curve by lines (false: markers only, a scatter plot).
    pub lines: bool,
}

/// Why a plot could not be drawn.
#[derive(Debug, thiserror::Error)]
#[error("plot {path}: {message}")]
pub struct PlotError {
    /// File.
    pub path: String,
    /// What went wrong.
    pub message: String,
}

impl Plot {
    fn usable(&self, (x, y): (f64, f64)) -> bool {
        x.is_finite() && y.is_finite() && (!self.log_y || y > 0.0)
    }

    /// Axis ranges over all usable points and lines, padded.
    fn ranges(&self) -> Option<((f64, f64), (f64, f64))> {
        let pts: Vec<(f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|&p| self.usable(p))
            .collect();
        if pts.is_empty() {
            return None;
        }
        let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY);
        for &(x, y) in &pts {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        for &(_, y) in &self.hlines {
            if self.usable((0.0, y)) {
                (y0, y1) = (y0.min(y), y1.max(y));
            }
        }
        if x1 <= x0 {
            let half = if x0 == 0.0 { 1.0 } else { 0.5 * x0.abs() };
            (x0, x1) = (x0 - half, x1 + half);
        } else if !self.lines {
            // a scatter plot: markers at the ends of the range clear of the axes
            let pad = 0.04 * (x1 - x0);
            (x0, x1) = (x0 - pad, x1 + pad);
        }
        if self.log_y {
            (y0, y1) = (y0 / 3.0, y1 * 3.0);
        } else if y1 <= y0 {
            (y0, y1) = (
                y0 - 0.5 * y0.abs().max(1e-12),
                y1 + 0.5 * y1.abs().max(1e-12),
            );
        } else {
            let pad = 0.05 * (y1 - y0);
            (y0, y1) = (y0 - pad, y1 + pad);
        }
        Some(((x0, x1), (y0, y1)))
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        let ((x0, x1), (y0, y1)) = self.ranges().ok_or("no finite data to plot")?;
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root);
        chart
            .caption(&self.title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(80);
        macro_rules! body {
            ($chart:expr) => {{
                let mut c = $chart;
                c.configure_mesh()
                    .x_desc(self.x_label.as_str())
                    .y_desc(self.y_label.as_str())
                    .x_label_formatter(&|v| tick(*v))
                    .y_label_formatter(&|v| tick(*v))
                    .label_style(("sans-serif", 13))
                    .axis_desc_style(("sans-serif", 15))
                    .draw()
                    .map_err(|e| e.to_string())?;
                let shown = self
                    .series
                    .iter()
                    .filter(|s| s.points.iter().any(|&p| self.usable(p)));
                for (i, s) in shown.enumerate() {
                    let color = Palette99::pick(i).to_rgba();
                    let pts: Vec<(f64, f64)> = s
                        .points
                        .iter()
                        .copied()
                        .filter(|&p| self.usable(p))
                        .collect();
                    let line = if self.lines { pts.clone() } else { Vec::new() };
                    c.draw_series(LineSeries::new(line, color.stroke_width(2)))
                        .map_err(|e| e.to_string())?
                        .label(s.label.as_str())
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                        });
                    if self.markers || !self.lines {
                        c.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                            .map_err(|e| e.to_string())?;
                    }
                }
                for (label, y) in &self.hlines {
                    let red = RED.stroke_width(1);
                    c.draw_series(LineSeries::new(vec![(x0, *y), (x1, *y)], red))
                        .map_err(|e| e.to_string())?
                        .label(label.as_str())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], red));
                }
                c.configure_series_labels()
                    .label_font(("sans-serif", 13))
                    .background_style(WHITE.mix(0.8))
                    .border_style(BLACK)
                    .draw()
                    .map_err(|e| e.to_string())?;
            }};
        }
        if self.log_y {
            body!(chart
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(|e| e.to_string())?);
        } else {
            body!(chart
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| e.to_string())?);
        }
        root.present().map_err(|e| e.to_string())
    }

    /// Write `STEM.png` and `STEM.svg` of `size` (width, height) pixels; returns both paths.
    pub fn write(&self, stem: &Path, size: (u32, u32)) -> Result<Vec<PathBuf>, PlotError> {
        register_font();
        let png = stem.with_extension("png");
        let svg = stem.with_extension("svg");
        let err = |p: &Path, message: String| PlotError {
            path: p.display().to_string(),
            message,
        };
        self.draw(BitMapBackend::new(&png, size).into_drawing_area())
            .map_err(|m| err(&png, m))?;
        self.draw(SVGBackend::new(&svg, size).into_drawing_area())
            .map_err(|m| err(&svg, m))?;
        Ok(vec![png, svg])
    }
}
