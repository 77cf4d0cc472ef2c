//! Line charts as inline SVG: axes with round ticks, a legend, and series
//! drawn as polylines (a series may change colour along its length, e.g.
//! by the constraint that limits the feed there).

use std::fmt::Write as _;

/// Drawing size of a chart (px).
const WIDTH: f64 = 960.0;
const HEIGHT: f64 = 300.0;
/// Margins: left for the y ticks, bottom for the x ticks and label.
const LEFT: f64 = 70.0;
const RIGHT: f64 = 16.0;
const TOP: f64 = 28.0;
const BOTTOM: f64 = 44.0;

/// A stretch of a series in one colour.
#[derive(Clone, Debug)]
pub struct Stretch {
    pub colour: &'static str,
    pub points: Vec<(f64, f64)>,
}

/// One curve of a chart.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text (none where empty).
    pub label: String,
    /// Colour of the legend entry (the stretches may differ).
    pub colour: &'static str,
    pub stretches: Vec<Stretch>,
    pub dashed: bool,
}

impl Series {
    /// A series in one colour.
    pub fn plain(label: &str, colour: &'static str, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.to_string(),
            colour,
            stretches: vec![Stretch { colour, points }],
            dashed: false,
        }
    }
}

/// A chart: title, axis labels, series; `log_y` plots the decimal logarithm
/// of y (values at or below `log_floor` drawn at the floor).
#[derive(Clone, Debug)]
pub struct Chart {
    pub id: String,
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Extra legend entries (colour, text), e.g. the constraints.
    pub keys: Vec<(&'static str, String)>,
    pub log_y: bool,
    pub log_floor: f64,
}

/// Round tick values covering `[lo, hi]`: steps of 1, 2 or 5 times a power
/// of ten, about `count` of them.
pub fn ticks(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    if hi <= lo || hi.is_nan() || lo.is_nan() || !lo.is_finite() || !hi.is_finite() {
        return vec![lo];
    }
    let raw = (hi - lo) / count.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

/// A number as a tick label: few digits, no trailing zeros.
pub fn label(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.0e}");
    }
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

impl Chart {
    fn y_of(&self, y: f64) -> f64 {
        if self.log_y {
            y.max(self.log_floor).log10()
        } else {
            y
        }
    }

    /// The chart as an `<svg>` element.
    pub fn svg(&self) -> String {
        let pts = || {
            self.series
                .iter()
                .flat_map(|s| &s.stretches)
                .flat_map(|s| &s.points)
        };
        let (x0, mut x1, mut y0, mut y1) = bounds(pts().map(|&(x, y)| (x, self.y_of(y))));
        if !self.log_y {
            y0 = y0.min(0.0);
        }
        if x1 <= x0 {
            x1 = x0 + 1.0;
        }
        if y1 <= y0 {
            y1 = y0 + 1.0;
        }
        let y1 = y1 + 0.05 * (y1 - y0);
        let (pw, ph) = (WIDTH - LEFT - RIGHT, HEIGHT - TOP - BOTTOM);
        let sx = |x: f64| LEFT + (x - x0) / (x1 - x0) * pw;
        let sy = |y: f64| TOP + ph - (y - y0) / (y1 - y0) * ph;
        let mut o = String::new();
        let _ = write!(
            o,
            r#"<svg class="chart" id="{}" viewBox="0 0 {WIDTH} {HEIGHT}" xmlns="http://www.w3.org/2000/svg">"#,
            self.id
        );
        let _ = write!(
            o,
            r#"<text class="title" x="{LEFT}" y="18">{}</text>"#,
            esc(&self.title)
        );
        // Grid and ticks.
        for t in ticks(x0, x1, 8) {
            let x = sx(t);
            let _ = write!(
                o,
                r#"<line class="grid" x1="{x:.1}" y1="{TOP}" x2="{x:.1}" y2="{:.1}"/><text class="tick" x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
                TOP + ph,
                TOP + ph + 16.0,
                label(t)
            );
        }
        for t in ticks(y0, y1, 5) {
            let y = sy(t);
            let text = if self.log_y {
                label(10f64.powf(t))
            } else {
                label(t)
            };
            let _ = write!(
                o,
                r#"<line class="grid" x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}"/><text class="tick" x="{:.1}" y="{:.1}" text-anchor="end">{text}</text>"#,
                LEFT + pw,
                LEFT - 6.0,
                y + 4.0
            );
        }
        let _ = write!(
            o,
            r#"<rect class="frame" x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}"/>"#
        );
        let _ = write!(
            o,
            r#"<text class="axis" x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            LEFT + pw / 2.0,
            HEIGHT - 6.0,
            esc(&self.x_label)
        );
        let _ = write!(
            o,
            r#"<text class="axis" transform="translate(14 {:.1}) rotate(-90)" text-anchor="middle">{}{}</text>"#,
            TOP + ph / 2.0,
            esc(&self.y_label),
            if self.log_y { " (log scale)" } else { "" }
        );
        // Series.
        for s in &self.series {
            for st in &s.stretches {
                if st.points.is_empty() {
                    continue;
                }
                let _ = write!(
                    o,
                    r#"<polyline class="series{}" stroke="{}" points=""#,
                    if s.dashed { " dashed" } else { "" },
                    st.colour
                );
                for &(x, y) in &st.points {
                    let _ = write!(o, "{:.1},{:.1} ", sx(x), sy(self.y_of(y)));
                }
                o.push_str(r#""/>"#);
            }
        }
        // Legend, top right.
        let entries: Vec<(&str, String, bool)> = self
            .series
            .iter()
            .filter(|s| !s.label.is_empty())
            .map(|s| (s.colour, s.label.clone(), s.dashed))
            .chain(self.keys.iter().map(|(c, t)| (*c, t.clone(), false)))
            .collect();
        let mut x = WIDTH - RIGHT;
        for (colour, text, dashed) in entries.iter().rev() {
            let w = 30.0 + 6.5 * text.chars().count() as f64;
            x -= w;
            let _ = write!(
                o,
                r#"<line class="key{}" stroke="{colour}" x1="{x:.1}" y1="14" x2="{:.1}" y2="14"/><text class="tick" x="{:.1}" y="18">{}</text>"#,
                if *dashed { " dashed" } else { "" },
                x + 18.0,
                x + 22.0,
                esc(text)
            );
        }
        o.push_str("</svg>");
        o
    }
}

/// The smallest box `(x0, x1, y0, y1)` holding the finite `points`, or
/// the unit box when there is none.
pub fn bounds(points: impl Iterator<Item = (f64, f64)>) -> (f64, f64, f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (x, y) in points.filter(|(x, y)| x.is_finite() && y.is_finite()) {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0.is_finite() {
        (x0, x1, y0, y1)
    } else {
        (0.0, 1.0, 0.0, 1.0)
    }
}

/// `text` escaped for HTML and SVG.
pub fn esc(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// At most about `2 * buckets` of `points` (sorted by x): in each of
/// `buckets` equal spans of x, the lowest and the highest point in their
/// order, so that no peak or dip is lost to the thinning.
pub fn thin(points: &[(f64, f64)], buckets: usize) -> Vec<(f64, f64)> {
    thin_indices(points, buckets)
        .into_iter()
        .map(|i| points[i])
        .collect()
}

/// The indices of the points [`thin`] keeps, in order.
pub fn thin_indices(points: &[(f64, f64)], buckets: usize) -> Vec<usize> {
    if points.len() <= 2 * buckets || buckets == 0 {
        return (0..points.len()).collect();
    }
    let (x0, x1) = (points[0].0, points[points.len() - 1].0);
    let span = (x1 - x0).max(f64::MIN_POSITIVE);
    let bucket = |x: f64| (((x - x0) / span) * buckets as f64) as usize;
    let mut out = Vec::with_capacity(2 * buckets + 2);
    let mut i = 0;
    while i < points.len() {
        let b = bucket(points[i].0);
        let mut j = i;
        let (mut lo, mut hi) = (i, i);
        while j < points.len() && bucket(points[j].0) == b {
            if points[j].1 < points[lo].1 {
                lo = j;
            }
            if points[j].1 > points[hi].1 {
                hi = j;
            }
            j += 1;
        }
        out.push(lo.min(hi));
        if lo != hi {
            out.push(lo.max(hi));
        }
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(ticks(0.0, 10.0, 5), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        let t = ticks(0.013, 0.087, 4);
        assert!(t.iter().all(|v| (0.013..=0.087).contains(v)));
        assert!(t.len() >= 3);
    }

    #[test]
    fn thinning_keeps_every_extreme() {
        let pts: Vec<(f64, f64)> = (0..10_000)
            .map(|i| (i as f64, if i == 5_001 { 100.0 } else { (i % 7) as f64 }))
            .collect();
        let t = thin(&pts, 100);
        assert!(t.len() <= 202);
        assert!(t.contains(&(5_001.0, 100.0)));
        assert!(t.windows(2).all(|w| w[0].0 <= w[1].0));
    }
}
