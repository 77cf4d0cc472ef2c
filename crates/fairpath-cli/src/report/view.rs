//! The path in one plane as a zoomable SVG: the tolerance band around the
//! original, the original, each method's written path, and markers.
//!
//! The band is the original drawn with a stroke `2 * tolerance` wide, round
//! joins and caps: the stroke of a polyline with round joins and caps is
//! its Minkowski sum with a disc of the stroke's half width, and the
//! projection of a tube (a path's Minkowski sum with a ball) onto a plane
//! is the projected path's Minkowski sum with the disc, so what is drawn is
//! exactly the band's projection (of the original as flattened for the
//! drawing).

use super::chart::esc;
use fairpath::geom::Vec3;
use std::fmt::Write as _;

/// A principal plane: the two axes drawn (0 = X, 1 = Y, 2 = Z).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plane {
    pub name: &'static str,
    pub axes: (usize, usize),
}

pub const XY: Plane = Plane {
    name: "XY",
    axes: (0, 1),
};
pub const XZ: Plane = Plane {
    name: "XZ",
    axes: (0, 2),
};
pub const YZ: Plane = Plane {
    name: "YZ",
    axes: (1, 2),
};

fn coord(p: Vec3, axis: usize) -> f64 {
    match axis {
        0 => p.x,
        1 => p.y,
        _ => p.z,
    }
}

/// Polylines of one kind in a view.
#[derive(Clone, Debug)]
pub struct Layer {
    pub label: String,
    pub colour: &'static str,
    /// `band`, `original`, `rapid` or `written` (the CSS class).
    pub class: &'static str,
    pub polylines: Vec<Vec<Vec3>>,
}

/// Points marked in a view.
#[derive(Clone, Debug)]
pub struct Markers {
    pub label: String,
    pub colour: &'static str,
    pub points: Vec<Vec3>,
}

/// The view as an `<svg>` element (y up), with its legend above it.
pub fn view_svg(
    id: &str,
    plane: Plane,
    tolerance: f64,
    layers: &[Layer],
    markers: &[Markers],
) -> String {
    let (a, b) = plane.axes;
    let (x0, x1, y0, y1) = super::chart::bounds(
        layers
            .iter()
            .flat_map(|l| &l.polylines)
            .flatten()
            .map(|p| (coord(*p, a), -coord(*p, b))),
    );
    let pad = 0.03 * (x1 - x0).max(y1 - y0).max(4.0 * tolerance);
    let (vx, vy, vw, vh) = (x0 - pad, y0 - pad, x1 - x0 + 2.0 * pad, y1 - y0 + 2.0 * pad);
    let mut o = String::new();
    let _ = write!(o, r#"<div class="legend">"#);
    for l in layers {
        let _ = write!(
            o,
            r#"<span><i class="{}" style="border-color:{}"></i>{}</span>"#,
            l.class,
            l.colour,
            esc(&l.label)
        );
    }
    for m in markers {
        let _ = write!(
            o,
            r#"<span><i class="dot" style="background:{}"></i>{} ({})</span>"#,
            m.colour,
            esc(&m.label),
            m.points.len()
        );
    }
    o.push_str("</div>");
    let _ = write!(
        o,
        r#"<svg class="pathview" id="{id}" data-plane="{}" viewBox="{vx} {vy} {vw} {vh}" preserveAspectRatio="xMidYMid meet" xmlns="http://www.w3.org/2000/svg">"#,
        plane.name
    );
    for l in layers {
        for line in &l.polylines {
            if line.len() < 2 {
                continue;
            }
            let _ = write!(o, r#"<polyline class="{}" stroke="{}""#, l.class, l.colour);
            if l.class == "band" {
                let _ = write!(o, r#" stroke-width="{}""#, 2.0 * tolerance);
            }
            o.push_str(r#" points=""#);
            for p in line {
                let _ = write!(o, "{} {} ", num(coord(*p, a)), num(-coord(*p, b)));
            }
            o.push_str(r#""/>"#);
        }
    }
    let r = vw.max(vh) / 300.0;
    for m in markers {
        for p in &m.points {
            let _ = write!(
                o,
                r#"<circle class="marker" fill="{}" cx="{}" cy="{}" r="{r}"/>"#,
                m.colour,
                num(coord(*p, a)),
                num(-coord(*p, b))
            );
        }
    }
    o.push_str("</svg>");
    o
}

/// A coordinate with a tenth of a micrometre's resolution, no trailing
/// zeros.
fn num(v: f64) -> String {
    let s = format!("{v:.5}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// `points` thinned to the vertices that keep every dropped point within
/// `epsilon` of the polyline kept (Douglas and Peucker 1973, iterative),
/// in 3D: each projection is then within `epsilon` too.
pub fn simplify(points: &[Vec3], epsilon: f64) -> Vec<Vec3> {
    if points.len() <= 2 {
        return points.to_vec();
    }
    let mut keep = vec![false; points.len()];
    keep[0] = true;
    keep[points.len() - 1] = true;
    let mut stack = vec![(0, points.len() - 1)];
    while let Some((i, j)) = stack.pop() {
        let (mut far, mut at) = (0.0, i);
        for (k, p) in points.iter().enumerate().take(j).skip(i + 1) {
            let d = fairpath::geom::point_segment_distance(*p, points[i], points[j]);
            if d > far {
                (far, at) = (d, k);
            }
        }
        if far > epsilon {
            keep[at] = true;
            stack.push((i, at));
            stack.push((at, j));
        }
    }
    points
        .iter()
        .zip(keep)
        .filter_map(|(p, k)| k.then_some(*p))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simplification_keeps_every_point_within_epsilon() {
        let pts: Vec<Vec3> = (0..2000)
            .map(|i| {
                let t = i as f64 * 0.01;
                Vec3::new(t, (3.0 * t).sin(), 0.1 * t)
            })
            .collect();
        let s = simplify(&pts, 0.001);
        assert!(s.len() < pts.len() / 2, "{}", s.len());
        for p in &pts {
            let d = s
                .windows(2)
                .map(|w| fairpath::geom::point_segment_distance(*p, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 0.001 + 1e-12, "{d}");
        }
    }

    #[test]
    fn the_band_is_twice_the_tolerance_wide() {
        let layer = Layer {
            label: "band".into(),
            colour: "#ccc",
            class: "band",
            polylines: vec![vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)]],
        };
        let svg = view_svg("v", XY, 0.05, &[layer], &[]);
        assert!(svg.contains(r#"stroke-width="0.1""#), "{svg}");
    }
}
