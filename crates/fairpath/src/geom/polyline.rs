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

/// A sparse uniform grid over a set of segments: each occupied cell lists
/// the segments whose bounding boxes, grown by the query radius, touch it.
/// Cells are kept as sorted `(cell key, segment)` pairs, so memory follows
/// the segments, not the bounding volume (a helix or a raster fills a small
/// part of its box).
#[derive(Clone, Debug)]
pub struct SegmentGrid {
    segs: Vec<(Vec3, Vec3)>,
    origin: Vec3,
    cell: f64,
    /// Sorted by key.
    items: Vec<(u64, u32)>,
    /// Cells examined while building (see [`SegmentGrid::cells_visited`]).
    visited: usize,
}

const KEY_BITS: u32 = 21;
const KEY_MAX: i64 = (1 << KEY_BITS) - 1;

impl SegmentGrid {
    /// Builds the index. `radius` (mm) is the largest query distance that
    /// will be answered exactly by [`SegmentGrid::nearest_within`]. The cell
    /// size is twice the radius, or the mean segment length if that is
    /// larger (so a short segment, grown by the radius, touches about 8
    /// cells), grown if needed so that the grid spans at most 2^21 cells per
    /// axis.
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
        let mean = if segs.is_empty() {
            1.0
        } else {
            total / segs.len() as f64
        };
        let ext = hi - lo;
        let span = ext.x.max(ext.y).max(ext.z) + 2.0 * radius;
        let mut cell = (2.0 * radius).max(mean).max(span / (KEY_MAX as f64 - 2.0));
        if !(cell > 0.0 && cell.is_finite()) {
            cell = 1.0;
        }
        let origin = lo - Vec3::new(radius, radius, radius);
        let mut g = SegmentGrid {
            segs,
            origin,
            cell,
            items: Vec::new(),
            visited: 0,
        };
        let mut items = Vec::with_capacity(g.segs.len() * 4);
        let mut visited = 0;
        for i in 0..g.segs.len() {
            visited += g.for_cells_of(i, radius, |k| items.push((k, i as u32)));
        }
        items.sort_unstable();
        g.items = items;
        g.visited = visited;
        g
    }

    fn coord(&self, v: f64, o: f64) -> i64 {
        (math::floor((v - o) / self.cell) as i64).clamp(0, KEY_MAX)
    }

    fn key(c: [i64; 3]) -> u64 {
        ((c[0] as u64) << (2 * KEY_BITS)) | ((c[1] as u64) << KEY_BITS) | c[2] as u64
    }

    /// Calls `f` with the key of every cell that a point within `grow` of
    /// segment `i` can fall in. A long segment is walked slab by slab along
    /// its dominant axis, so it visits about `L / cell + 3` slabs of at
    /// most 36 cells (a cell is at least twice `grow`) rather than its
    /// whole bounding box (a 170 mm diagonal over 0.04 mm cells has 1.6e10
    /// cells in its box, at most 1.5e5 along it); with the cell at least the
    /// mean segment length, all segments together visit `O(n)` cells.
    /// Returns the number of cells examined.
    fn for_cells_of(&self, i: usize, grow: f64, mut f: impl FnMut(u64)) -> usize {
        let (a, b) = self.segs[i];
        let o = [self.origin.x, self.origin.y, self.origin.z];
        let (pa, pb) = ([a.x, a.y, a.z], [b.x, b.y, b.z]);
        let long = a.dist(b) > 2.0 * self.cell;
        let half_diag = 0.5 * self.cell * math::sqrt(3.0);
        // Cells from `c0` to `c1`, those far from a long segment skipped.
        let mut visited = 0;
        let mut visit = |c0: [i64; 3], c1: [i64; 3]| {
            visited += (0..3)
                .map(|k| (c1[k] - c0[k] + 1).max(0) as usize)
                .product::<usize>();
            for x in c0[0]..=c1[0] {
                for y in c0[1]..=c1[1] {
                    for z in c0[2]..=c1[2] {
                        if long {
                            let centre = self.origin
                                + Vec3::new(x as f64 + 0.5, y as f64 + 0.5, z as f64 + 0.5)
                                    * self.cell;
                            if point_segment_distance(centre, a, b) > half_diag + grow {
                                continue;
                            }
                        }
                        f(Self::key([x, y, z]));
                    }
                }
            }
        };
        // Cells of a box grown by `grow`.
        let cells = |lo: [f64; 3], hi: [f64; 3]| -> ([i64; 3], [i64; 3]) {
            (
                core::array::from_fn(|k| self.coord(lo[k] - grow, o[k])),
                core::array::from_fn(|k| self.coord(hi[k] + grow, o[k])),
            )
        };
        let lo: [f64; 3] = core::array::from_fn(|k| pa[k].min(pb[k]));
        let hi: [f64; 3] = core::array::from_fn(|k| pa[k].max(pb[k]));
        let (c0, c1) = cells(lo, hi);
        if !long {
            visit(c0, c1);
            return visited;
        }
        // A long segment is walked slab by slab across its dominant axis
        // `m`: slab `s` gets the cells around the part of the segment whose
        // `m` coordinate lies within `grow` of it, that part widened by a
        // whole cell on each side (far above the rounding of the
        // parameters). A point within `grow` of the segment lies within
        // `grow` of such a part in every coordinate.
        let d: [f64; 3] = core::array::from_fn(|k| pb[k] - pa[k]);
        let m = (0..3)
            .max_by(|&j, &k| math::abs(d[j]).total_cmp(&math::abs(d[k])))
            .unwrap_or(0);
        for s in c0[m]..=c1[m] {
            let w0 = o[m] + (s - 1) as f64 * self.cell - grow;
            let w1 = o[m] + (s + 2) as f64 * self.cell + grow;
            let (u, v) = ((w0 - pa[m]) / d[m], (w1 - pa[m]) / d[m]);
            let (t0, t1) = (u.min(v).clamp(0.0, 1.0), u.max(v).clamp(0.0, 1.0));
            let q0: [f64; 3] = core::array::from_fn(|k| pa[k] + d[k] * t0);
            let q1: [f64; 3] = core::array::from_fn(|k| pa[k] + d[k] * t1);
            let (mut s0, mut s1) = cells(
                core::array::from_fn(|k| q0[k].min(q1[k])),
                core::array::from_fn(|k| q0[k].max(q1[k])),
            );
            s0[m] = s;
            s1[m] = s;
            visit(s0, s1);
        }
        visited
    }

    /// Cells examined while the index was built: a measure of its work.
    /// At most `208 n` for `n` segments: a segment up to two cells long
    /// spans at most 4 cells per axis (64), a longer one `L / cell + 3`
    /// slabs of at most 36 cells, and since the cell is at least the mean
    /// segment length, the lengths over the cell sum to at most `n`.
    pub fn cells_visited(&self) -> usize {
        self.visited
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
        let mut c = [0i64; 3];
        for k in 0..3 {
            let f = math::floor((v[k] - o[k]) / self.cell);
            if !(0.0..=KEY_MAX as f64).contains(&f) {
                return None;
            }
            c[k] = f as i64;
        }
        let key = Self::key(c);
        let start = self.items.partition_point(|&(k, _)| k < key);
        let mut best: Option<(f64, usize)> = None;
        for &(k, i) in &self.items[start..] {
            if k != key {
                break;
            }
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
