//! Line charts as standalone SVG files (no fonts or native libraries needed): several named series of (x, y)
//! points, linear or logarithmic axes with 1-2-5 / decade ticks, a legend. Used for speed-vs-accuracy and
//! throughput charts (`prism bench`, `prism converge`, the sampling comparison).

use prism_core::error::{PrismError, Result};
use std::fmt::Write as _;
use std::path::Path;

#[derive(Clone, Debug, Default)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// Extra marks on a chart: horizontal reference lines (e.g. a reference image's own noise) and series drawn dashed
/// (e.g. a peer renderer's). Kept apart from [`Chart`] so that existing charts need not name them.
#[derive(Clone, Debug, Default)]
pub struct Decor {
    /// `(label, y)`: a dashed grey line across the plot at `y`, labelled at its right end.
    pub hlines: Vec<(String, f64)>,
    /// Names of the series drawn dashed.
    pub dashed: Vec<String>,
}

#[derive(Clone, Debug, Default)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub log_x: bool,
    pub log_y: bool,
    pub series: Vec<Series>,
}

const W: f64 = 760.0;
const H: f64 = 480.0;
const LEFT: f64 = 80.0;
const RIGHT: f64 = 200.0;
/// A generous width of one legend character at the 12 px sans-serif font (digits and lower case are narrower):
/// the chart widens to fit its longest label instead of cutting it at the edge.
const LEGEND_CHAR: f64 = 7.2;
/// Legend swatch, gap before the text, and margin after it.
const LEGEND_PAD: f64 = 14.0 + 28.0 + 12.0;
const TOP: f64 = 40.0;
const BOTTOM: f64 = 60.0;
const COLORS: [&str; 8] = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"];

struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
}

impl Axis {
    fn new(values: impl Iterator<Item = f64>, log: bool) -> Axis {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        if !lo.is_finite() {
            (lo, hi) = if log { (1.0, 10.0) } else { (0.0, 1.0) };
        }
        if log {
            lo = 10f64.powf(lo.log10().floor());
            hi = 10f64.powf(hi.log10().ceil());
            if hi <= lo {
                hi = lo * 10.0;
            }
        } else {
            let span = if hi > lo { hi - lo } else { hi.abs().max(1.0) };
            let step = nice_step(span / 5.0);
            lo = (lo / step).floor() * step;
            hi = (hi / step).ceil() * step;
            if hi <= lo {
                hi = lo + step;
            }
        }
        Axis { lo, hi, log }
    }

    /// Position in [0, 1] along the axis.
    fn t(&self, v: f64) -> f64 {
        if self.log {
            (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }

    fn ticks(&self) -> Vec<f64> {
        if self.log {
            let mut out = vec![];
            let mut d = self.lo;
            while d <= self.hi * 1.0001 {
                for m in [1.0, 2.0, 5.0] {
                    if d * m <= self.hi * 1.0001 {
                        out.push(d * m);
                    }
                }
                d *= 10.0;
            }
            out
        } else {
            let step = nice_step((self.hi - self.lo) / 5.0);
            let mut out = vec![];
            let mut v = self.lo;
            while v <= self.hi + step * 1e-6 {
                out.push(v);
                v += step;
            }
            out
        }
    }
}

fn nice_step(raw: f64) -> f64 {
    let mag = 10f64.powf(raw.abs().max(1e-300).log10().floor());
    let f = raw / mag;
    mag * if f <= 1.0 {
        1.0
    } else if f <= 2.0 {
        2.0
    } else if f <= 5.0 {
        5.0
    } else {
        10.0
    }
}

fn label(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1e4 || v.abs() < 1e-3 {
        format!("{v:.0e}")
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

impl Chart {
    pub fn to_svg(&self) -> String {
        self.to_svg_with(&Decor::default())
    }

    /// The chart with `decor`'s reference lines and dashed series. Every series is a `<polyline class="curve">`
    /// with its name in `data-series` (a page test can check that each curve was drawn).
    pub fn to_svg_with(&self, decor: &Decor) -> String {
        let pts = || self.series.iter().flat_map(|s| s.points.iter().copied());
        let xa = Axis::new(pts().map(|p| p.0), self.log_x);
        let ya = Axis::new(pts().map(|p| p.1).chain(decor.hlines.iter().map(|h| h.1)), self.log_y);
        let (pw, ph) = (W - LEFT - RIGHT, H - TOP - BOTTOM);
        let longest = self.series.iter().map(|s| s.name.chars().count()).max().unwrap_or(0);
        let w = LEFT + pw + RIGHT.max(LEGEND_PAD + LEGEND_CHAR * longest as f64).ceil();
        let px = |v: f64| LEFT + xa.t(v) * pw;
        let py = |v: f64| TOP + (1.0 - ya.t(v)) * ph;
        let mut s = String::new();
        let _ = write!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{H}" viewBox="0 0 {w} {H}" font-family="sans-serif" font-size="12">"#
        );
        let _ = write!(s, r#"<rect width="{w}" height="{H}" fill="white"/>"#);
        let _ = write!(
            s,
            r#"<text x="{}" y="24" text-anchor="middle" font-size="15">{}</text>"#,
            LEFT + pw / 2.0,
            esc(&self.title)
        );
        for t in xa.ticks() {
            let x = px(t);
            let _ = write!(s, r##"<line x1="{x:.1}" y1="{TOP}" x2="{x:.1}" y2="{:.1}" stroke="#e4e4e4"/>"##, TOP + ph);
            let _ =
                write!(s, r#"<text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"#, TOP + ph + 16.0, label(t));
        }
        for t in ya.ticks() {
            let y = py(t);
            let _ =
                write!(s, r##"<line x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#e4e4e4"/>"##, LEFT + pw);
            let _ =
                write!(s, r#"<text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"#, LEFT - 6.0, y + 4.0, label(t));
        }
        let _ = write!(s, r##"<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" stroke="#333"/>"##);
        let _ = write!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            LEFT + pw / 2.0,
            H - 18.0,
            esc(&self.x_label)
        );
        let _ = write!(
            s,
            r#"<text x="18" y="{:.1}" text-anchor="middle" transform="rotate(-90 18 {:.1})">{}</text>"#,
            TOP + ph / 2.0,
            TOP + ph / 2.0,
            esc(&self.y_label)
        );
        for (label, y) in &decor.hlines {
            if !(y.is_finite() && (!self.log_y || *y > 0.0)) {
                continue;
            }
            let y = py(*y);
            let _ = write!(
                s,
                r##"<line x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#777" stroke-dasharray="2 3"/>"##,
                LEFT + pw
            );
            let _ = write!(
                s,
                r##"<text x="{:.1}" y="{:.1}" text-anchor="end" fill="#555" font-size="11">{}</text>"##,
                LEFT + pw - 4.0,
                y - 4.0,
                esc(label)
            );
        }
        for (i, series) in self.series.iter().enumerate() {
            let color = COLORS[i % COLORS.len()];
            let visible: Vec<(f64, f64)> = series
                .points
                .iter()
                .copied()
                .filter(|(x, y)| {
                    x.is_finite() && y.is_finite() && (!self.log_x || *x > 0.0) && (!self.log_y || *y > 0.0)
                })
                .collect();
            let path: Vec<String> = visible.iter().map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y))).collect();
            let dash = if decor.dashed.contains(&series.name) { r#" stroke-dasharray="6 4""# } else { "" };
            let _ = write!(
                s,
                r#"<polyline class="curve" data-series="{}" points="{}" fill="none" stroke="{color}" stroke-width="2"{dash}/>"#,
                esc(&series.name),
                path.join(" ")
            );
            for &(x, y) in &visible {
                let _ = write!(s, r#"<circle cx="{:.1}" cy="{:.1}" r="3" fill="{color}"/>"#, px(x), py(y));
            }
            let ly = TOP + 10.0 + 20.0 * i as f64;
            let lx = LEFT + pw + 14.0;
            let _ = write!(
                s,
                r#"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="{color}" stroke-width="2"{dash}/>"#,
                lx + 22.0
            );
            let _ = write!(s, r#"<text x="{}" y="{}">{}</text>"#, lx + 28.0, ly + 4.0, esc(&series.name));
        }
        s.push_str("</svg>\n");
        s
    }

    pub fn write_svg(&self, path: &Path) -> Result<()> {
        std::fs::write(path, self.to_svg()).map_err(|e| PrismError::io(path, e))
    }
}
