//! HTML pieces of the report page: escaping, figures, tables, colour bars, problem boxes, and the page itself
//! with its style sheet. Static markup only: no script, no network, every picture a file beside the page or an
//! inline SVG.

use super::images::Scale;
use std::fmt::Write as _;

/// Text as HTML (also safe inside attribute values).
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// A picture with a caption (`caption` is HTML). `width` is the displayed width in CSS pixels; small images are
/// enlarged with square pixels.
pub fn figure(src: &str, alt: &str, width: u32, caption: &str, class: &str) -> String {
    format!(
        r#"<figure class="{class}"><img src="{}" alt="{}" width="{width}" loading="eager"><figcaption>{caption}</figcaption></figure>"#,
        esc(src),
        esc(alt)
    )
}

/// The displayed width of an image `w` pixels wide: enlarged by the integer factor nearest to `target / w` (at
/// least 1), so small images show with square pixels at about `target` CSS pixels.
pub fn shown_width(w: u32, target: u32) -> u32 {
    w * ((target as f64 / w.max(1) as f64).round() as u32).max(1)
}

/// A figure that stands where a picture could not be made: the error, in a box of the picture's size.
pub fn failed_figure(width: u32, title: &str, message: &str) -> String {
    format!(
        r#"<figure class="shot"><div class="failed" style="width:{width}px;min-height:{}px"><b>{}</b><code>{}</code></div><figcaption>{}</figcaption></figure>"#,
        width.min(320) * 3 / 4,
        esc(title),
        esc(message),
        esc(title)
    )
}

/// A table: `head` cells are text, `rows` cells HTML; `align` has one letter per column, `l` or `r` (numbers).
pub fn table(head: &[&str], align: &str, rows: &[Vec<String>], class: &str) -> String {
    let right: Vec<bool> = align.chars().map(|c| c == 'r').collect();
    let mut s = format!(r#"<table class="{class}"><thead><tr>"#);
    for (i, h) in head.iter().enumerate() {
        let cls = if right.get(i).copied().unwrap_or(false) { r#" class="num""# } else { "" };
        let _ = write!(s, "<th{cls}>{}</th>", esc(h));
    }
    s += "</tr></thead><tbody>";
    for r in rows {
        s += "<tr>";
        for (i, c) in r.iter().enumerate() {
            let cls = if right.get(i).copied().unwrap_or(false) { r#" class="num""# } else { "" };
            let _ = write!(s, "<td{cls}>{c}</td>");
        }
        s += "</tr>";
    }
    s + "</tbody></table>"
}

/// A horizontal colour bar for `scale` from 0 to `max`, labelled with `label` (inline SVG); with `log`, colours
/// follow `ln(1 + v) / ln(1 + max)` and the ticks are placed accordingly.
pub fn colour_bar(scale: Scale, max: f64, log: bool, label: &str, id: &str) -> String {
    let mut stops = String::new();
    for i in 0..=10 {
        let t = i as f32 / 10.0;
        let [r, g, b] = scale(t);
        let _ = write!(stops, r#"<stop offset="{t}" stop-color="rgb({r},{g},{b})"/>"#);
    }
    let ticks: String = (0..=4)
        .map(|i| {
            let t = i as f64 / 4.0;
            let v = if log { ((1.0 + max).ln() * t).exp() - 1.0 } else { max * t };
            let x = 10.0 + 300.0 * t;
            format!(
                r##"<line x1="{x}" y1="24" x2="{x}" y2="28" stroke="#444"/><text x="{x}" y="40" text-anchor="middle">{}</text>"##,
                num(v)
            )
        })
        .collect();
    format!(
        r##"<svg class="bar" width="760" height="44" viewBox="0 0 760 44" font-size="11.5" font-family="sans-serif" role="img" aria-label="{l}"><defs><linearGradient id="{id}">{stops}</linearGradient></defs><rect x="10" y="6" width="300" height="18" fill="url(#{id})" stroke="#444" stroke-width="0.5"/>{ticks}<text x="326" y="20">{l}{scale_note}</text></svg>"##,
        l = esc(label),
        scale_note = if log { " (logarithmic scale)" } else { "" }
    )
}

/// A number with three significant digits (no exponent between 0.001 and 10^6).
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return "-".into();
    }
    let a = v.abs();
    if a == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e6).contains(&a) {
        return format!("{v:.2e}");
    }
    let decimals = (2 - a.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
}

/// A red box naming a problem (also listed at the top of the page).
pub fn problem_box(item: &str, message: &str) -> String {
    format!(r#"<div class="problem"><b>{}</b>: <code>{}</code></div>"#, esc(item), esc(message))
}

/// The whole page: header, table of contents, problems, sections, footer.
pub struct Page<'a> {
    pub title: &'a str,
    pub intro: &'a str,
    /// `(anchor, title)` of each section.
    pub toc: &'a [(String, String)],
    pub problems: &'a [super::Problem],
    pub body: &'a str,
    pub footer: &'a str,
}

impl Page<'_> {
    pub fn render(&self) -> String {
        let mut s = String::from("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">");
        s += r#"<meta name="viewport" content="width=device-width, initial-scale=1">"#;
        let _ = write!(s, "<title>{}</title><style>{CSS}</style></head><body>", esc(self.title));
        let _ = write!(s, r#"<header><h1>{}</h1><p class="intro">{}</p><nav>"#, esc(self.title), self.intro);
        for (anchor, title) in self.toc {
            let _ = write!(s, r##"<a href="#{}">{}</a>"##, esc(anchor), esc(title));
        }
        s += "</nav></header><main>";
        if !self.problems.is_empty() {
            let _ = write!(
                s,
                r#"<section class="problems" id="problems"><h2>{} problem{}</h2><p>These items could not be measured; everything else was.</p><ul>"#,
                self.problems.len(),
                if self.problems.len() == 1 { "" } else { "s" }
            );
            for p in self.problems {
                let _ = write!(
                    s,
                    "<li><b>{} / {}</b>: <code>{}</code></li>",
                    esc(&p.section),
                    esc(&p.item),
                    esc(&p.message)
                );
            }
            s += "</ul></section>";
        }
        s += self.body;
        let _ = writeln!(s, "</main><footer>{}</footer></body></html>", self.footer);
        s
    }
}

const CSS: &str = r#"
:root{--ink:#1d2330;--muted:#5b6475;--line:#d9dee7;--bg:#f6f7fa;--card:#fff;--accent:#2a5db0;--bad:#b3261e}
*{box-sizing:border-box}
body{margin:0;font:15px/1.5 system-ui,-apple-system,"Segoe UI",Roboto,"Helvetica Neue",Arial,sans-serif;color:var(--ink);background:var(--bg)}
header{background:linear-gradient(135deg,#16213a,#2a3f6e);color:#fff;padding:28px 40px 18px}
header h1{margin:0 0 6px;font-size:28px;font-weight:650;letter-spacing:.2px}
header .intro{max-width:1000px;margin:0 0 14px;color:#d6def0}
header .intro a{color:#fff}
nav{display:flex;flex-wrap:wrap;gap:6px}
nav a{color:#fff;text-decoration:none;background:rgba(255,255,255,.12);padding:3px 10px;border-radius:12px;font-size:13px}
nav a:hover{background:rgba(255,255,255,.25)}
main{max-width:1320px;margin:0 auto;padding:10px 28px 30px}
section{background:var(--card);border:1px solid var(--line);border-radius:10px;padding:18px 24px 22px;margin:22px 0;box-shadow:0 1px 3px rgba(20,30,50,.06)}
h2{margin:4px 0 6px;font-size:22px}
h3{margin:18px 0 8px;font-size:16px;color:#2c3446}
.caption,.note{color:var(--muted);max-width:1050px}
.charts{display:grid;grid-template-columns:repeat(auto-fit,minmax(420px,1fr));gap:14px;margin:10px 0}
.charts svg{width:100%;height:auto;border:1px solid var(--line);border-radius:6px}
.strip{display:flex;flex-wrap:wrap;gap:14px;align-items:flex-start;margin:8px 0}
figure{margin:0}
figure.shot img,figure.map img,figure.crop img{display:block;image-rendering:pixelated;border-radius:4px;border:1px solid #cfd5df;height:auto}
figcaption{font-size:12.5px;color:var(--muted);max-width:300px;margin-top:4px}
figcaption b{color:var(--ink)}
.pair{display:flex;flex-direction:column;gap:6px}
table{border-collapse:collapse;margin:8px 0;font-size:13.5px}
th,td{padding:4px 10px;border-bottom:1px solid var(--line);text-align:left;vertical-align:top}
th{background:#eef1f6;font-weight:600}
tbody tr:nth-child(even){background:#fafbfd}
th.num{text-align:right}
td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}
td.best{font-weight:700}
.problem,.failed{border:1px solid var(--bad);background:#fdf0ef;color:var(--bad);border-radius:6px;padding:8px 12px;margin:8px 0}
.rejected{border:1px solid #4b8a4b;background:#eef7ee;color:#1f4d1f;border-radius:6px;padding:8px 12px;width:220px;display:flex;flex-direction:column;gap:6px;font-size:12.5px}
.rejected code{white-space:pre-wrap;word-break:break-word}
.failed{display:flex;flex-direction:column;gap:6px;font-size:12.5px}
.failed code{white-space:pre-wrap;word-break:break-word;color:#5a1410}
section.problems{border-color:var(--bad)}
section.problems h2{color:var(--bad)}
.cases{display:flex;flex-direction:column;gap:18px}
article.case{border:1px solid var(--line);border-radius:8px;padding:12px 16px;background:#fcfcfe}
article.case h3{margin-top:4px}
details{margin:8px 0}
summary{cursor:pointer;color:var(--accent)}
code{font-family:ui-monospace,SFMono-Regular,Menlo,Consolas,monospace;font-size:12.5px}
svg.bar{display:block;margin:2px 0 8px}
footer{max-width:1320px;margin:0 auto;padding:0 28px 40px;color:var(--muted);font-size:13px}
footer code{background:#eceff4;padding:1px 5px;border-radius:4px}
"#;
