//! Distance from a point to segments and polylines, and a uniform-grid index
//! that answers "nearest segment" queries on large paths in O(1) average time.

use super::Vec3;
use crate::math;
use alloc::vec::Vec;

/// Distance from `q` to the segment `a b` (exact, up to rounding).
pub fn point_segment_distance(q: Vec3, a: Vec3, b: Vec3) -> f64 {
    let (d, _) = point_segment_distance_t(q, a, b);
    d
}

/// Distance from `q` to segment `a b` and the parameter `t` in `[0, 1]` of
/// the nearest point.
pub fn point_segment_distance_t(q: Vec3, a: Vec3, b: Vec3) -> (f64, f64) {
    let ab = b - a;
    let l2 = ab.norm_sq();
    let t = if l2 > 0.0 {
        ((q - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((a + ab * t).dist(q), t)
}

/// Distance from `q` to the polyline through `pts`, with the index of the
/// nearest segment (brute force, O(n); see [`SegmentGrid`] for many queries).
/// A single point counts as a degenerate polyline.
pub fn distance_to_polyline(q: Vec3, pts: &[Vec3]) -> Option<(f64, usize)> {
    match pts.len() {
        0 => None,
        1 => Some((q.dist(pts[0]), 0)),
        _ => pts
            .windows(2)
            .enumerate()
            .map(|(i, w)| (point_segment_distance(q, w[0], w[1]), i))
            .min_by(|a, b| a.0.total_cmp(&b.0)),
    }
}

/// A uniform grid over a set of segments: each cell lists the segments whose
/// bounding boxes (grown by the cell size) touch it.
#[derive(Clone, Debug)]
pub struct SegmentGrid {
    segs: Vec<(Vec3, Vec3)>,
    origin: Vec3,
    cell: f64,
    dims: [usize; 3],
    start: Vec<u32>,
    items: Vec<u32>,
}

impl SegmentGrid {
    /// Builds the index. `radius` (mm) is the largest query distance that
    /// will be answered exactly by [`SegmentGrid::nearest_within`]; the cell
    /// size is chosen from it and from the segment lengths so that long
    /// segments do not fill too many cells.
    pub fn new(segs: Vec<(Vec3, Vec3)>, radius: f64) -> SegmentGrid {
        let mut lo = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let mut hi = -lo;
        let mut total = 0.0;
        for &(a, b) in &segs {
            for p in [a, b] {
                lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
                hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
            }
            total += a.dist(b);
        }
        if segs.is_empty() {
            lo = Vec3::ZERO;
            hi = Vec3::ZERO;
        }
        let ext = hi - lo;
        let mean = if segs.is_empty() {
            1.0
        } else {
            total / segs.len() as f64
        };
        // Cell at least the query radius, around the mean segment length,
        // and no more than ~4 cells per segment in total.
        let vol_cells_max = (4 * segs.len().max(1)) as f64;
        let mut cell = radius.max(mean).max(1e-6);
        loop {
            let n = |e: f64| (math::floor(e / cell) + 1.0).max(1.0);
            if n(ext.x) * n(ext.y) * n(ext.z) <= vol_cells_max.max(64.0) {
                break;
            }
            cell *= 1.5;
        }
        let dims = [
            (math::floor(ext.x / cell) as usize) + 1,
            (math::floor(ext.y / cell) as usize) + 1,
            (math::floor(ext.z / cell) as usize) + 1,
        ];
        let ncell = dims[0] * dims[1] * dims[2];
        let mut g = SegmentGrid {
            segs,
            origin: lo,
            cell,
            dims,
            start: Vec::new(),
            items: Vec::new(),
        };
        // Two passes: count, then fill (CSR layout).
        let mut count = alloc::vec![0u32; ncell + 1];
        for i in 0..g.segs.len() {
            g.for_cells_of(i, radius, |c| count[c + 1] += 1);
        }
        for i in 0..ncell {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut items = alloc::vec![0u32; count[ncell] as usize];
        for i in 0..g.segs.len() {
            g.for_cells_of(i, radius, |c| {
                items[fill[c] as usize] = i as u32;
                fill[c] += 1;
            });
        }
        g.start = count;
        g.items = items;
        g
    }

    fn cell_coord(&self, v: f64, o: f64, n: usize) -> usize {
        let c = math::floor((v - o) / self.cell);
        if c < 0.0 {
            0
        } else {
            (c as usize).min(n - 1)
        }
    }

    fn for_cells_of(&self, i: usize, grow: f64, mut f: impl FnMut(usize)) {
        let (a, b) = self.segs[i];
        let lo = [
            a.x.min(b.x) - grow,
            a.y.min(b.y) - grow,
            a.z.min(b.z) - grow,
        ];
        let hi = [
            a.x.max(b.x) + grow,
            a.y.max(b.y) + grow,
            a.z.max(b.z) + grow,
        ];
        let o = [self.origin.x, self.origin.y, self.origin.z];
        let c0: [usize; 3] = core::array::from_fn(|k| self.cell_coord(lo[k], o[k], self.dims[k]));
        let c1: [usize; 3] = core::array::from_fn(|k| self.cell_coord(hi[k], o[k], self.dims[k]));
        let dir = b - a;
        let len = dir.norm();
        for x in c0[0]..=c1[0] {
            for y in c0[1]..=c1[1] {
                for z in c0[2]..=c1[2] {
                    // Skip cells far from a long diagonal segment.
                    if len > 2.0 * self.cell {
                        let centre = self.origin
                            + Vec3::new(x as f64 + 0.5, y as f64 + 0.5, z as f64 + 0.5) * self.cell;
                        let half_diag = 0.5 * self.cell * math::sqrt(3.0);
                        if point_segment_distance(centre, a, b) > half_diag + grow {
                            continue;
                        }
                    }
                    f((x * self.dims[1] + y) * self.dims[2] + z);
                }
            }
        }
    }

    /// Number of segments indexed.
    pub fn len(&self) -> usize {
        self.segs.len()
    }
    pub fn is_empty(&self) -> bool {
        self.segs.is_empty()
    }
    /// The indexed segments.
    pub fn segments(&self) -> &[(Vec3, Vec3)] {
        &self.segs
    }

    /// Nearest segment to `q` if one lies within the `radius` given at
    /// construction: `(distance, segment index)`. `None` means every segment
    /// is farther than that radius.
    pub fn nearest_within(&self, q: Vec3) -> Option<(f64, usize)> {
        let o = [self.origin.x, self.origin.y, self.origin.z];
        let v = [q.x, q.y, q.z];
        let mut c = [0usize; 3];
        for k in 0..3 {
            let f = math::floor((v[k] - o[k]) / self.cell);
            if f < 0.0 || f >= self.dims[k] as f64 {
                return None;
            }
            c[k] = f as usize;
        }
        let id = (c[0] * self.dims[1] + c[1]) * self.dims[2] + c[2];
        let (s, e) = (self.start[id] as usize, self.start[id + 1] as usize);
        let mut best: Option<(f64, usize)> = None;
        for &i in &self.items[s..e] {
            let (a, b) = self.segs[i as usize];
            let d = point_segment_distance(q, a, b);
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, i as usize));
            }
        }
        best
    }

    /// Nearest segment to `q` at any distance: the grid answer when it is
    /// within the indexed radius, else a brute-force scan.
    pub fn nearest(&self, q: Vec3, radius: f64) -> Option<(f64, usize)> {
        match self.nearest_within(q) {
            Some((d, i)) if d <= radius => Some((d, i)),
            _ => self
                .segs
                .iter()
                .enumerate()
                .map(|(i, &(a, b))| (point_segment_distance(q, a, b), i))
                .min_by(|a, b| a.0.total_cmp(&b.0)),
        }
    }
}
