//! Points of a run's polyline sampled along it and bucketed in a uniform
//! grid: the samples near a point, for the bridge and crowding checks of
//! the gates and the band's heights of the width argument.

use super::gates::point_at;
use crate::geom::Vec3;
use crate::math;
use alloc::vec::Vec;

/// Points of a polyline every `step` of arc length, in a uniform grid of
/// cells of `cell` mm, to find the samples near a point.
pub(super) struct SampleGrid {
    /// `(arc length, point)`, in order along the polyline.
    pub(super) samples: Vec<(f64, Vec3)>,
    order: Vec<([i64; 3], usize)>,
    cell: f64,
}

impl SampleGrid {
    pub(super) fn new(pts: &[Vec3], s: &[f64], step: f64, cell: f64) -> SampleGrid {
        let total = *s.last().unwrap_or(&0.0);
        let n = (total / step) as usize + 1;
        let samples: Vec<(f64, Vec3)> = (0..=n)
            .map(|i| {
                let x = (i as f64 * step).min(total);
                (x, point_at(pts, s, x))
            })
            .collect();
        let mut g = SampleGrid {
            samples,
            order: Vec::new(),
            cell,
        };
        let mut order: Vec<([i64; 3], usize)> = g
            .samples
            .iter()
            .enumerate()
            .map(|(i, (_, p))| (g.key(*p), i))
            .collect();
        order.sort_unstable();
        g.order = order;
        g
    }

    fn key(&self, p: Vec3) -> [i64; 3] {
        [
            math::floor(p.x / self.cell) as i64,
            math::floor(p.y / self.cell) as i64,
            math::floor(p.z / self.cell) as i64,
        ]
    }

    /// Calls `f` with the arc length and point of every sample in the
    /// cells around `q` (every sample within `cell` of it among them) until
    /// it returns `true`; whether one did.
    pub(super) fn any_near(&self, q: Vec3, mut f: impl FnMut(f64, Vec3) -> bool) -> bool {
        let k = self.key(q);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let kk = [k[0] + dx, k[1] + dy, k[2] + dz];
                    let lo = self.order.partition_point(|(c, _)| *c < kk);
                    for &(c, j) in &self.order[lo..] {
                        if c != kk {
                            break;
                        }
                        let (xj, pj) = self.samples[j];
                        if f(xj, pj) {
                            return true;
                        }
                    }
                }
            }
        }
        false
    }
}
