//! The walls of a corner (module docs of [`super`], step 9): where the
//! band is bounded on the outer sides of both legs and across the turn's
//! plane, a path that passes the corner must turn there, and its speed
//! somewhere near it is capped.

use super::gates::{point_at, Bridges};
use super::width::Heights;
use crate::geom::Vec3;
use crate::math;

/// A speed every band path falls below near a corner: at most `speed`
/// somewhere within distance `reach` of the corner's vertex `at` (within
/// arc length `pi / (2 K)` of where the path passes it, `K` the walls'
/// least curvature, which is within `e + r` of the vertex).
#[derive(Clone, Copy, Debug)]
pub(super) struct WallCap {
    pub(super) at: Vec3,
    pub(super) speed: f64,
    pub(super) reach: f64,
}

/// Two caps of one corner, each sound: any cap bounds the run, but the
/// chain of slow points is not monotone in the windows it is given, so
/// both are tried (module docs of [`super`], step 10).
#[derive(Clone, Copy, Debug)]
pub(super) struct Caps {
    /// The lowest speed proved, of the longest sweep that proves it.
    pub(super) slowest: WallCap,
    /// The lowest speed (within [`SPEED_SLACK`]) at the shortest reach.
    pub(super) nearest: WallCap,
}

/// The polyline's run and the band's constants the walls are built from.
pub(super) struct Corner<'a> {
    pub(super) pts: &'a [Vec3],
    pub(super) s: &'a [f64],
    /// The band's half-width `e` (tolerance plus flattening chord).
    pub(super) e: f64,
    /// Step 1's reach `r`: where the path passes a point `c(x)` of the run
    /// it is within `e` of a point of `c([x - r, x])` and of one of
    /// `c([x, x + r])` (`0`: within `e` of `c(x)`, paths in order).
    pub(super) reach: f64,
    /// Bridges of the run (`None`: paths in order, which need none).
    pub(super) bridges: Option<&'a Bridges>,
    pub(super) heights: &'a Heights,
}

/// The least of `n . c(y)` over the polyline between arc lengths `lo` and
/// `hi` (a linear function's least on a polyline is at a vertex or an
/// end).
fn least_along(pts: &[Vec3], s: &[f64], lo: f64, hi: f64, n: Vec3) -> f64 {
    let mut least = n.dot(point_at(pts, s, lo)).min(n.dot(point_at(pts, s, hi)));
    let a = s.partition_point(|&v| v < lo);
    let b = s.partition_point(|&v| v <= hi);
    for p in &pts[a..b.max(a)] {
        least = least.min(n.dot(*p));
    }
    least
}

/// The highest `n . c` over the stretch of the run through arc length
/// `x` that stays within `radius` of `c(x)` (to where it first leaves
/// that ball either way): where a path in order can be matched while it
/// stays in the ball around where it passes `c(x)`. Its matched stretch
/// of the run is connected, holds `x` and stays within the ball, so the
/// run's other passes through the ball (a raster's neighbouring pass)
/// do not count.
fn top_connected(pts: &[Vec3], s: &[f64], x: f64, radius: f64, n: Vec3) -> f64 {
    let v = point_at(pts, s, x);
    // Where the segment from `a` (inside) to `b` (outside) leaves the
    // ball.
    let exit = |a: Vec3, b: Vec3| {
        let (d, w) = (b - a, a - v);
        let (dd, wd) = (d.dot(d), w.dot(d));
        let t = if dd > 0.0 {
            let disc = (wd * wd - dd * (w.dot(w) - radius * radius)).max(0.0);
            ((-wd + math::sqrt(disc)) / dd).clamp(0.0, 1.0)
        } else {
            0.0
        };
        a + d * t
    };
    let mut top = n.dot(v);
    let i = s.partition_point(|&u| u <= x);
    let mut prev = v;
    for &p in &pts[i.min(pts.len())..] {
        if p.dist(v) > radius {
            top = top.max(n.dot(exit(prev, p)));
            break;
        }
        top = top.max(n.dot(p));
        prev = p;
    }
    prev = v;
    for &p in pts[..i.min(pts.len())].iter().rev() {
        if p.dist(v) > radius {
            top = top.max(n.dot(exit(prev, p)));
            break;
        }
        top = top.max(n.dot(p));
        prev = p;
    }
    top
}

/// The least eigenvalue of `sum n_i n_i^T / w_i` over the two unit
/// vectors `n1`, `n2` (a 2x2 problem in their plane).
fn least_eigen_pair(n1: Vec3, w1: f64, n2: Vec3, w2: f64) -> f64 {
    let tr = 1.0 / w1 + 1.0 / w2;
    let sin2 = n1.cross(n2).norm_sq();
    let det = sin2 / (w1 * w2);
    0.5 * (tr - math::sqrt((tr * tr - 4.0 * det).max(0.0)))
}

/// Widest angle (rad) between neighbouring walls of the fan
/// ([`fan_walls`]): a tangent inside the fan's cone is then within half of
/// it of a wall, so `|nu . T| >= cos 15 deg`, above `sin(theta / 2)` for
/// every turn `theta` up to 150 degrees, where the cone's two edges decide.
const FAN_STEP: f64 = core::f64::consts::PI / 6.0;

/// Most walls in the fan: a reversal's cone of `pi` at [`FAN_STEP`].
const FAN_MAX: usize = 7;

/// Halvings of the bisection of [`fan_curvature`]: `2^-48` of its range.
const FAN_HALVINGS: u32 = 48;

/// Relative margin taken off [`fan_curvature`]'s result for the rounding
/// of the arcs' ends in [`fan_covers`] (a few ulps of `pi`).
const FAN_ROUNDING: f64 = 1e-12;

/// Turns of the tangent (rad) over which the walls' argument follows the
/// path from where it passes the vertex (module docs of [`super`], step
/// 9): a quarter turn proves the most curvature, a shorter one keeps the
/// slow point nearer the vertex and proves as much where the tangent
/// meets no wall steeper than it (a right angle's worst, 45 degrees).
const SWEEPS: [f64; 4] = [
    core::f64::consts::FRAC_PI_2,
    core::f64::consts::FRAC_PI_3,
    core::f64::consts::FRAC_PI_4,
    core::f64::consts::FRAC_PI_6,
];

/// Caps whose speeds are within this share of the lowest count as equal
/// (the bisections' rounding), and the one of the shortest reach is taken
/// ([`nearer`]).
const SPEED_SLACK: f64 = 1e-9;

/// Of two caps, the lower speed, or where they are within
/// [`SPEED_SLACK`], the shorter reach.
fn nearer(a: WallCap, b: WallCap) -> WallCap {
    let slow = a.speed.min(b.speed);
    let near = |c: &WallCap| c.speed <= slow * (1.0 + SPEED_SLACK);
    match (near(&a), near(&b)) {
        (true, true) => {
            if b.reach < a.reach {
                b
            } else {
                a
            }
        }
        (true, false) => a,
        _ => b,
    }
}

/// The walls in the turn's plane that every corner has (module docs of
/// [`super`], step 9, "the fan"): the unit normals `nu` with `nu . u1 >= 0`
/// and `nu . u2 <= 0`, on which the legs' stretch is lowest at the vertex,
/// from the first leg's outer normal `n1` to the second's `n2`, at most
/// [`FAN_STEP`] apart. Each comes with its angle in the plane, from `u1`
/// towards `u2` (`n1` at `-pi / 2`, `n2` at `theta - pi / 2`).
fn fan_walls(u1: Vec3, u2: Vec3) -> impl Iterator<Item = (f64, Vec3)> {
    let cos = u1.dot(u2).clamp(-1.0, 1.0);
    let theta = math::acos(cos);
    // `y` completes `u1` to the plane's basis: `u2 = cos x + sin y`.
    let y = (u2 - u1 * cos).normalized(1e-9).unwrap_or(Vec3::ZERO);
    let gaps = (math::ceil(theta / FAN_STEP) as usize).clamp(1, FAN_MAX - 1);
    (0..=gaps).map(move |k| {
        let angle = -core::f64::consts::FRAC_PI_2 + theta * k as f64 / gaps as f64;
        (angle, u1 * math::cos(angle) + y * math::sin(angle))
    })
}

/// The least angle `beta` (rad) between a tangent and a wall that makes
/// the path rise at least `rise` (curvature times distance, `k w`) towards
/// it within the turn `gamma` of its tangent (arc length `gamma / k`):
/// the rise is `cos(max(beta - gamma, 0)) - cos beta`, which grows with
/// `beta`; `None` where even `pi / 2` does not.
fn least_angle(rise: f64, gamma: f64) -> Option<f64> {
    use core::f64::consts::FRAC_PI_2;
    if rise <= 1.0 - math::cos(gamma) {
        return Some(math::acos(1.0 - rise));
    }
    // cos(beta - gamma) - cos(beta) = 2 sin(beta - gamma / 2) sin(gamma / 2).
    let x = rise / (2.0 * math::sin(0.5 * gamma));
    if x > 1.0 {
        return None;
    }
    let beta = 0.5 * gamma + math::atan2(x, math::sqrt(1.0 - x * x));
    (beta <= FRAC_PI_2).then_some(beta)
}

/// Whether walls at `(angle, w)` in a plane cover every direction of it
/// at curvature `k`, the path followed through a turn `gamma` of its
/// tangent: each covers the tangents `t` whose angle to it, `asin |nu .
/// t|`, is at least [`least_angle`] of `k w`, the arcs of directions (mod
/// `pi`) within `pi / 2` less that angle of its own.
fn fan_covers(fan: &[(f64, f64)], k: f64, gamma: f64) -> bool {
    use core::f64::consts::PI;
    let mut arcs = [(0.0f64, 0.0f64); 2 * FAN_MAX];
    let mut n = 0;
    for &(angle, w) in fan {
        let Some(beta) = least_angle(k * w, gamma) else {
            continue;
        };
        let half = 0.5 * PI - beta;
        if half >= 0.5 * PI {
            return true;
        }
        let x = angle - half;
        let start = x - PI * math::floor(x / PI);
        let end = start + 2.0 * half;
        if end > PI {
            arcs[n] = (start, PI);
            arcs[n + 1] = (0.0, end - PI);
            n += 2;
        } else {
            arcs[n] = (start, end);
            n += 1;
        }
    }
    let arcs = &mut arcs[..n];
    arcs.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let mut reach = 0.0;
    for &(start, end) in arcs.iter() {
        if start > reach {
            return false;
        }
        reach = f64::max(reach, end);
    }
    reach >= PI
}

/// A curvature every path through the corner exceeds near the vertex,
/// from the fan's walls at `(angle, w)` (module docs of [`super`], step 9,
/// "the fan"): the largest `k` at which they cover every direction of the
/// plane ([`fan_covers`]), by bisection, the lower end of its last
/// bracket; 0 where none. At a right angle with every `w = 2e`,
/// `(1 - cos 45 deg) / (2e)`: the widest circle inside the band.
fn fan_curvature(fan: &[(f64, f64)], gamma: f64) -> f64 {
    let widest = fan.iter().map(|f| f.1).fold(f64::INFINITY, f64::min);
    if fan.is_empty() || !(widest > 0.0 && widest.is_finite()) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0 / widest);
    if fan_covers(fan, hi, gamma) {
        return hi * (1.0 - FAN_ROUNDING);
    }
    for _ in 0..FAN_HALVINGS {
        let mid = 0.5 * (lo + hi);
        if fan_covers(fan, mid, gamma) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo * (1.0 - FAN_ROUNDING)
}

impl Corner<'_> {
    /// The caps of step 9 at the polyline's point of arc length `x` (a
    /// vertex where the run turns), for balls of radius `radii` (mm)
    /// around it ([`Caps`]), or `None`. `speed_of` gives the largest speed
    /// at which a curvature can be run.
    pub(super) fn cap(&self, x: f64, radii: &[f64], speed_of: impl Fn(f64) -> f64) -> Option<Caps> {
        let (pts, s, e, r) = (self.pts, self.s, self.e, self.reach);
        let total = *s.last()?;
        if x - r <= 0.0 || x + r >= total {
            return None;
        }
        if self.bridges.is_some_and(|b| b.spans(x)) {
            return None;
        }
        let v = point_at(pts, s, x);
        // The legs' directions within the reach, or a polyline step.
        let back = point_at(pts, s, (x - r.max(e)).max(0.0));
        let ahead = point_at(pts, s, (x + r.max(e)).min(total));
        let u1 = (v - back).normalized(e * 1e-6)?;
        let u2 = (ahead - v).normalized(e * 1e-6)?;
        let cos = u1.dot(u2);
        // Outer normals of the legs (away from the other leg) and the
        // turn's plane normal.
        let n1 = (u1 * cos - u2).normalized(1e-9)?;
        let n2 = (u1 - u2 * cos).normalized(1e-9)?;
        let b = u1.cross(u2).normalized(1e-9)?;
        let (start, end) = (pts[0], *pts.last()?);
        let mut slowest: Option<WallCap> = None;
        let mut nearest: Option<WallCap> = None;
        for &rb in radii {
            // Run ends farther than the ball: the path goes on for at
            // least `rb - (e + r)` either side of where it passes `x`.
            if start.dist(v) < rb || end.dist(v) < rb {
                continue;
            }
            // w = e - (n . p - H) at the path's point p passing x: that
            // point is within e of c(x1) and of c(x2), x - r <= x1 <= x
            // <= x2 <= x + r.
            let top = |n: Vec3| match self.bridges {
                Some(_) => self.heights.top(v, rb + e, n),
                None => top_connected(pts, s, x, rb + e, n),
            };
            let lows = |n: Vec3| {
                (
                    least_along(pts, s, x - r, x, n),
                    least_along(pts, s, x, x + r, n),
                )
            };
            let w = |n: Vec3| {
                let (lo_a, lo_b) = lows(n);
                2.0 * e + top(n) - lo_a.max(lo_b)
            };
            let (w1, w2) = (w(n1), w(n2));
            let wb = w(b).min(w(-b));
            if !(w1 > 0.0 && w2 > 0.0 && wb > 0.0) {
                continue;
            }
            // K >= max_i (n_i . T)^2 / (2 w_i) >= lambda_min(sum n_i n_i^T
            // / (6 w_i)) over the three walls.
            let k_three = (least_eigen_pair(n1, w1, n2, w2).min(1.0 / wb)) / 6.0;
            // The fan of walls in the turn's plane, tilted across it.
            let spread = [b, -b]
                .iter()
                .map(|&n| {
                    let (lo_a, lo_b) = lows(n);
                    top(n) - lo_a.min(lo_b)
                })
                .fold(0.0, f64::max);
            let mut fan = [(0.0, 0.0); FAN_MAX];
            let mut walls = 0;
            for (slot, (angle, n)) in fan.iter_mut().zip(fan_walls(u1, u2)) {
                let lift = w(n) - 2.0 * e;
                *slot = (angle, 2.0 * e + math::sqrt(lift * lift + spread * spread));
                walls += 1;
            }
            // For every kappa < K whose arc gamma / kappa fits in the
            // ball's room, the curvature exceeds kappa within that arc
            // length of the passing point: its speed is below the speed of
            // kappa, so at most that of K.
            let room = rb - e - r;
            for &gamma in &SWEEPS {
                let mut k = fan_curvature(&fan[..walls], gamma);
                if gamma == core::f64::consts::FRAC_PI_2 {
                    k = k.max(k_three);
                }
                if !(room > 0.0 && k.is_finite() && k > 0.0 && gamma / k <= room) {
                    continue;
                }
                let cap = WallCap {
                    at: v,
                    speed: speed_of(k),
                    reach: gamma / k + e + r,
                };
                // The same speed proved by a shorter sweep (up to the
                // bisection's rounding) leaves the longer one.
                if slowest.is_none_or(|c| cap.speed < c.speed * (1.0 - FAN_ROUNDING)) {
                    slowest = Some(cap);
                }
                nearest = Some(match nearest {
                    None => cap,
                    Some(b) => nearer(b, cap),
                });
            }
        }
        slowest.map(|s| Caps {
            slowest: s,
            nearest: nearest.unwrap_or(s),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_least_eigenvalue_of_two_walls_is_the_weaker_when_square_and_zero_when_parallel() {
        let (x, y) = (Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
        let l = least_eigen_pair(x, 0.1, y, 0.2);
        assert!((l - 5.0).abs() < 1e-12, "{l}");
        assert!(least_eigen_pair(x, 0.1, x, 0.1).abs() < 1e-12);
        // At 60 degrees, equal weights: eigenvalues (1 +- cos 60) / w.
        let n = Vec3::new(0.5, 0.75f64.sqrt(), 0.0);
        let l = least_eigen_pair(x, 0.1, n, 0.1);
        assert!((l - 5.0).abs() < 1e-9, "{l}");
    }

    /// The caps at arc length 10 of the run `pts` (arc lengths `s`) for
    /// paths in order, balls of 1, 1.5 and 3 mm, under `k^2 v^3 <= 20000`.
    fn caps_at_ten(pts: &[Vec3], s: &[f64], e: f64) -> Option<Caps> {
        let heights = Heights::new(pts, s, 0.5 * e, 5.0 + e);
        let corner = Corner {
            pts,
            s,
            e,
            reach: 0.0,
            bridges: None,
            heights: &heights,
        };
        corner.cap(10.0, &[1.0, 1.5, 3.0], |k| math::cbrt(20000.0 / (k * k)))
    }

    /// The right angle (0,0) -> (10,0) -> (10,10) in the plane z = 0.
    fn right_angle() -> (alloc::vec::Vec<Vec3>, alloc::vec::Vec<f64>) {
        let pts = alloc::vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(10.0, 10.0, 0.0),
        ];
        (pts, alloc::vec![0.0, 10.0, 20.0])
    }

    #[test]
    fn a_right_angle_caps_the_speed_at_the_widest_circle_inside_the_band() {
        // Every wall of the fan is 2e from where a path in order passes
        // the vertex (the run's own stretch through the ball, exact): K >=
        // (1 - cos 45 deg) / (2e), the curvature of the circle tangent to
        // both outer walls through the band's inner corner.
        let (pts, s) = right_angle();
        let e = 0.05;
        let step = 0.5 * e;
        let heights = Heights::new(&pts, &s, step, 5.0 + e + step);
        let corner = Corner {
            pts: &pts,
            s: &s,
            e,
            reach: 0.0,
            bridges: None,
            heights: &heights,
        };
        let speed_of = |k: f64| math::cbrt(20000.0 / (k * k));
        let caps = corner.cap(10.0, &[1.0, 1.5, 3.0], speed_of).expect("a cap");
        let cap = caps.nearest;
        let k = (1.0 - 0.5f64.sqrt()) / (2.0 * e);
        // The quarter turn proves the same speed, farther out.
        let far = caps.slowest;
        assert!((far.speed - cap.speed).abs() < 1e-9 * cap.speed, "{caps:?}");
        let quarter = core::f64::consts::FRAC_PI_2 / k + e;
        assert!((far.reach - quarter).abs() < 1e-6, "{caps:?}");
        assert!(
            (cap.speed - speed_of(k)).abs() < 1e-9 * cap.speed,
            "{cap:?}"
        );
        assert!(cap.speed >= speed_of(k), "{cap:?}");
        assert!(cap.at.dist(Vec3::new(10.0, 0.0, 0.0)) < 1e-12);
        // The arc length within which the speed falls below the cap, plus
        // the path's distance from the vertex: an eighth of a turn proves
        // as much as a quarter, where the worst tangent meets its walls at
        // 45 degrees.
        let reach = core::f64::consts::FRAC_PI_4 / k + e;
        assert!((cap.reach - reach).abs() < 1e-6, "{cap:?}");
        // Straight on, no cap; a ball too small for the shortest sweep,
        // none.
        assert!(corner.cap(5.0, &[1.0, 1.5, 3.0], speed_of).is_none());
        assert!(corner.cap(10.0, &[0.2], speed_of).is_none());
    }

    #[test]
    fn seeded_planar_turns_find_the_widest_circle_inside_the_band() {
        // With every wall 2e away, the fan's curvature is that of the
        // circle tangent to both outer walls through the band's inner
        // corner, (1 - cos(theta / 2)) / (2e): a band path, so no sound
        // bound exceeds it, and up to 150 degrees the fan's edges reach
        // it. Sharper, the walls between them cover the cone's middle at
        // cos 15 deg at least.
        let mut rng = crate::seeded::Rng(94);
        for _ in 0..400 {
            let theta = 1e-3 + (core::f64::consts::PI - 2e-3) * rng.next();
            let e = rng.decades(-4.0, 0.0);
            let u1 = Vec3::new(1.0, 0.0, 0.0);
            let u2 = Vec3::new(math::cos(theta), math::sin(theta), 0.0);
            let fan: alloc::vec::Vec<(f64, f64)> =
                fan_walls(u1, u2).map(|(a, _)| (a, 2.0 * e)).collect();
            let k = fan_curvature(&fan, core::f64::consts::FRAC_PI_2);
            let circle = (1.0 - math::cos(0.5 * theta)) / (2.0 * e);
            assert!(
                k <= circle,
                "theta {theta}: {k} above the circle's {circle}"
            );
            let floor = if theta <= 5.0 * core::f64::consts::PI / 6.0 {
                circle
            } else {
                // `|nu . t| >= cos(FAN_STEP / 2)` for every direction `t`.
                (1.0 - math::sin(0.5 * FAN_STEP)) / (2.0 * e)
            };
            assert!(
                k >= floor * (1.0 - 1e-9),
                "theta {theta}: {k} below {floor}"
            );
        }
    }

    #[test]
    fn seeded_least_angles_rise_as_the_sweep_allows() {
        // The rise within a sweep `gamma` at angle `beta`, `cos(max(beta
        // - gamma, 0)) - cos beta`, is what `least_angle` inverts: the
        // angle it returns rises exactly that much, and a quarter turn is
        // `acos(1 - rise)`.
        let rise = |beta: f64, gamma: f64| math::cos((beta - gamma).max(0.0)) - math::cos(beta);
        let mut rng = crate::seeded::Rng(9402);
        for _ in 0..2000 {
            let gamma = 0.05 + (core::f64::consts::FRAC_PI_2 - 0.05) * rng.next();
            let beta = core::f64::consts::FRAC_PI_2 * rng.next();
            let r = rise(beta, gamma);
            let found = least_angle(r, gamma).expect("an angle");
            assert!(
                (found - beta).abs() < 1e-6,
                "gamma {gamma} beta {beta} found {found}"
            );
            let quarter = least_angle(r, core::f64::consts::FRAC_PI_2).unwrap();
            assert!((quarter - math::acos(1.0 - r)).abs() < 1e-12);
            // Beyond what a right angle to the wall gives, none.
            assert!(
                least_angle(rise(core::f64::consts::FRAC_PI_2, gamma) * 1.001, gamma).is_none()
            );
        }
        // A right angle's fan proves as much within an eighth of a turn as
        // within a quarter; within a twelfth, less.
        let u1 = Vec3::new(1.0, 0.0, 0.0);
        let u2 = Vec3::new(0.0, 1.0, 0.0);
        let fan: alloc::vec::Vec<(f64, f64)> = fan_walls(u1, u2).map(|(a, _)| (a, 0.1)).collect();
        let quarter = fan_curvature(&fan, core::f64::consts::FRAC_PI_2);
        let eighth = fan_curvature(&fan, core::f64::consts::FRAC_PI_4);
        let twelfth = fan_curvature(&fan, core::f64::consts::FRAC_PI_6);
        assert!(
            (quarter - eighth).abs() < 1e-9 * quarter,
            "{quarter} {eighth}"
        );
        assert!(twelfth < 0.95 * quarter, "{twelfth} {quarter}");
    }

    #[test]
    fn seeded_fan_walls_span_the_cone_between_the_outer_normals() {
        let mut rng = crate::seeded::Rng(9401);
        for _ in 0..200 {
            let unit = |rng: &mut crate::seeded::Rng| {
                Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5).normalized(1e-3)
            };
            let (Some(u1), Some(u2)) = (unit(&mut rng), unit(&mut rng)) else {
                continue;
            };
            let cos = u1.dot(u2);
            if cos.abs() > 1.0 - 1e-6 {
                continue;
            }
            let walls: alloc::vec::Vec<(f64, Vec3)> = fan_walls(u1, u2).collect();
            assert!(walls.len() >= 2 && walls.len() <= FAN_MAX);
            let n1 = (u1 * cos - u2).normalized(1e-9).unwrap();
            let n2 = (u1 - u2 * cos).normalized(1e-9).unwrap();
            assert!(walls[0].1.dist(n1) < 1e-9 && walls.last().unwrap().1.dist(n2) < 1e-9);
            for w in walls.windows(2) {
                assert!(w[1].0 - w[0].0 <= FAN_STEP + 1e-12);
                assert!((w[1].1.dot(w[0].1) - math::cos(w[1].0 - w[0].0)).abs() < 1e-9);
            }
            for &(_, n) in &walls {
                // A wall: both legs run no higher on it than the vertex.
                assert!(n.dot(u1) >= -1e-12 && n.dot(u2) <= 1e-12, "{n:?}");
                assert!((n.norm() - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn a_right_angle_turned_in_space_keeps_its_cap() {
        // The fan's frame comes from the legs alone: a rotated corner has
        // the same cap (the walls' heights are sampled on the same run).
        let (pts, s) = right_angle();
        let e = 0.05;
        let cap_of = |pts: &[Vec3]| caps_at_ten(pts, &s, e).expect("a cap").slowest.speed;
        let flat = cap_of(&pts);
        let k = Vec3::new(1.0, 2.0, 3.0).normalized(0.0).unwrap();
        let (sn, cs) = (math::sin(0.7), math::cos(0.7));
        let turned: alloc::vec::Vec<Vec3> = pts
            .iter()
            .map(|&p| p * cs + k.cross(p) * sn + k * (k.dot(p) * (1.0 - cs)))
            .collect();
        let spun = cap_of(&turned);
        assert!((flat - spun).abs() < 1e-9 * flat, "{flat} {spun}");
    }

    #[test]
    fn a_leg_out_of_the_turns_plane_lowers_no_cap_below_the_plane_s() {
        // A third leg out of the plane inside the ball widens the walls
        // tilted across the plane (the spread); the fan's curvature can
        // only fall, its speed only rise.
        let e = 0.05;
        let cap_of = |z: f64| {
            let pts = alloc::vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(10.0, 0.0, 0.0),
                Vec3::new(10.0, 0.5, 0.0),
                Vec3::new(10.0, 10.0, z),
            ];
            let s: alloc::vec::Vec<f64> = pts
                .iter()
                .scan((0.0, pts[0]), |acc, &p| {
                    acc.0 += acc.1.dist(p);
                    acc.1 = p;
                    Some(acc.0)
                })
                .collect();
            caps_at_ten(&pts, &s, e).map(|c| c.slowest.speed)
        };
        let flat = cap_of(0.0).expect("a cap");
        let tilted = cap_of(3.0).expect("a cap");
        assert!(tilted >= flat * (1.0 - 1e-12), "{tilted} {flat}");
    }

    #[test]
    fn a_neighbouring_pass_does_not_raise_the_walls_of_paths_in_order() {
        // A raster: along y = 0, a step-over, back along y = 1. Around
        // (5, 0) the ball of radius 1.5 holds the return pass, 1 above;
        // a path in order there is matched to the first pass only.
        let pts = alloc::vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(10.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let s = alloc::vec![0.0, 10.0, 11.0, 21.0];
        let up = Vec3::new(0.0, 1.0, 0.0);
        assert_eq!(top_connected(&pts, &s, 5.0, 1.5, up), 0.0);
        let heights = Heights::new(&pts, &s, 0.025, 2.0);
        let all = heights.top(Vec3::new(5.0, 0.0, 0.0), 1.5, up);
        assert!(all >= 1.0, "{all}");
        // The stretch leaves the ball along the pass: its ends there.
        let along = Vec3::new(1.0, 0.0, 0.0);
        assert!((top_connected(&pts, &s, 5.0, 1.5, along) - 6.5).abs() < 1e-12);
    }
}
