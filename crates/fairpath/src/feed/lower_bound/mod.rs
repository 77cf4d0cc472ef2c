//! A lower bound on the machining time of any path inside the tolerance
//! band of a run (issue 21, item 2): what no smoothing can beat under the
//! planner's limits.
//!
//! # The model it bounds
//! The planner's (`plan.rs`): a path is run with a speed profile `v(t)`
//! along its arc length with `v <= F` (the run's largest feed),
//! `|dv/dt| <= A` and `|d2v/dt2| <= J` (the double-S profiles; `A` and `J`
//! may be lowered by shaping, never raised), pointwise curvature caps
//! `k v^2 <= A_n` and, with [`MachineLimits::jerk_on_curves`],
//! `k^2 v^3 <= J`; every run starts and ends at rest with zero
//! acceleration ([`super::plan::RunEnds::AtRest`]). Per-axis limits, the
//! chord-error cap, `|dk/ds| v^3 <= J` and shaping only slow a plan
//! further and are dropped (a relaxation). The planner checks its caps at
//! the ends and middle of stretches of chord-error length, so a plan
//! follows this model up to that sampling.
//!
//! # The relaxation, step by step (each step proven below)
//! Let `e` be the tolerance plus the flattening chord (the original is
//! replaced by a polyline within the chord of it, so any band path is
//! within `e` of the polyline `c(s)`). `T_-(s)` is the band around
//! `c([0, s])`, `T_+(s)` around `c([s, L])`.
//!
//! 1. **Gates.** For a point `q = c(s)`, let `tau(s)` be the first time the
//!    path is in `T_+(s)`. Just before it the path was in `T_-(s)` (the two
//!    cover the band), so by closedness `x = path(tau(s))` is within `e` of
//!    some `c(s1)`, `s1 <= s`, and some `c(s2)`, `s2 >= s`. If no two points
//!    `s1 <= s <= s2` with `s2 - s1 > r` are within `2e` of each other (no
//!    "bridge", checked on samples of the polyline with the sampling step
//!    added to `2e`), both lie within arc length `r` of `s`; if there the
//!    polyline is monotone along the direction `d` of its chord over
//!    `[s - r, s + r]` and within `delta` of the line through `q` along `d`,
//!    then `|x - q| <= e + delta` (split `x - q` along `d`: the point on
//!    the far side in `d` is at least as far along `d`; the rest is the
//!    triangle inequality). `tau` is nondecreasing in `s`, so gates are
//!    passed in order, and the path's length between two gates is at least
//!    `|q_i - q_j| - rho_i - rho_j` (`rho = e + delta`). The run's ends are
//!    gates of radius 0 (kept exactly). Where the run comes back within
//!    `2e` of itself (closed contours, passes closer than the band) no
//!    gate can be placed, and a band path may cut across. For paths that
//!    follow the run in order ([`BandPaths::InOrder`]: within `e` of
//!    `c(s)` at a non-decreasing time `tau(s)`, Frechet distance at most
//!    the tolerance) a gate of radius `e` stands at every point, and the
//!    steps below hold as they are. The bound takes the straight gates
//!    (radius `e + delta`, as above), also where the run comes back near
//!    itself farther along it than [`BoundOptions::hairpin_reach`] (not
//!    at a sharp hairpin's tip, which the corner methods cut), where no
//!    straight gate stands but the run turns gently (a glyph's bowl, a
//!    small loop; [`BoundOptions::curved_turn`], `curved.rs`) a gate of
//!    radius `e` on it, and a gate
//!    of radius `e` on the tip of every exact reversal on legs longer
//!    than a short move ([`BoundOptions::reversal_half_angle`],
//!    [`BoundOptions::reversal_min_leg`]: a V-carve spike, a stroke
//!    retraced), which every method keeps as a corner, with the straight
//!    gates along its legs (the leg coming back is no hairpin; the
//!    bound is the larger of those with and without these gates,
//!    [`lower_bound_time`]);
//!    [`crate::verify::follows_in_order`] checks a path passes those
//!    gates in order (a path that cuts across does not).
//! 2. **Turns.** Between the gates `a < a+1 <= b < b+1` the mean directions
//!    of travel over `[tau_a, tau_a+1]` and `[tau_b, tau_b+1]` are within
//!    `asin((rho_a + rho_a+1) / |q_a+1 - q_a|)` of the chords' directions.
//!    A mean direction lies in the convex cone of the tangents it
//!    averages; a tangent curve of total turning `Theta < pi` on the
//!    sphere lies in a cap of radius `Theta/2` (around its middle point),
//!    which is convex; so the tangent turns by at least
//!    `alpha = angle(chords) - slacks` over `[tau_a, tau_b+1]`.
//! 3. **Rotation time.** The tangent turns at `omega = k v`; the caps give
//!    `omega <= A_n / v` and `omega <= sqrt(J / v)`. If the speed in the
//!    window stays `>= c`, the window lasts at least
//!    `alpha max(c / A_n, sqrt(c / J))`.
//! 4. **Speed envelopes.** With `v <= F` at all times and `|j| <= J`, an
//!    acceleration `a > 0` still raises the speed by `a^2 / (2J)`, so
//!    `|a| <= sqrt(2 J (F - v))` (by time reversal also when braking);
//!    from rest with `a = 0`, `a^2 - 2 J v` does not grow while `a > 0`, so
//!    `a <= sqrt(2 J v)` (and the same towards the end at rest). With
//!    `|a| <= A`, `d v / d x = a / v <= g(v) / v`: the speed at distance `x`
//!    from a point of speed `<= c` is at most the solution of that
//!    equation (tabulated conservatively, `Envelope`: between speed nodes
//!    the acceleration is taken at its largest there, and the time along
//!    that profile, `dv / a` per node, is exact for it). Both caps from
//!    rest hold along the whole run (`Rise::RunWide`). From a point `P`
//!    of speed `c` where the acceleration away from it is at most 0, `a <=
//!    J t` after it, so the speed is at most that of the profile that
//!    rises at jerk `J` from `c`, where `a^2 = 2 J (v - c)`
//!    (`Rise::Valley`; by comparison of the solutions of `dv/dt <=
//!    min(J t, A, sqrt(2 J (F - v)))`); its time to a distance is the
//!    least of any such start, a lower start speed only taking longer.
//!    A stretch's time under two envelopes, one from each end, is at
//!    least the first's time up to any split point plus the second's
//!    after it; the split where they meet gives the most.
//! 5. **Zones.** Turns with disjoint windows split the run at gates between
//!    them into zones, whose times add up. In a zone with a turn, let `c`
//!    be the least speed in its window, at a point `P`. Inside the window
//!    `a(P) = 0` (a minimum of a smooth speed), so both sides of `P` are
//!    valleys; at the window's start the speed does not fall after `P`
//!    (`a(P) >= 0`: a valley before it), at its end it does not rise
//!    before it (a valley after it); the other side has the run-wide
//!    caps. At the window's end the speed goes on falling after `P` to
//!    the next zero `m` of the acceleration; for a distance `d`, either
//!    `m` lies within `d` after `P` (a valley both ways at `m`, of speed
//!    at most `c`), or the speed stays at most `c` for `d` after `P` and
//!    is still falling there (a valley after that point); mirrored at the
//!    window's start. The zone's time is at least the time over its
//!    length under the envelopes from its ends (free: `F`; run ends: from
//!    rest) and from these slow points, the least over their places (a
//!    grid of cells, each bounded by its ends plus its width at `F`), and
//!    at least the rotation time plus the rest of its length at `F`. The
//!    bound takes the least over `c` (a grid, each cell bounded by its
//!    ends, both terms being monotone in `c`). Longer stretches never take
//!    less time (a profile over a longer stretch, scaled down in speed,
//!    runs a shorter one in the same time within every limit), so the
//!    length lower bounds may stand for the lengths.
//! 6. **Rest to rest.** Whatever its turns, a run is a motion along its
//!    arc length from rest to rest (zero acceleration at both ends) under
//!    `v <= F`, `|dv/dt| <= A`, `|d2v/dt2| <= J`. The least time of such a
//!    motion over a length `L` is the double-S with `v0 = v1 = 0` and the
//!    largest peak speed (Biagiotti & Melchiorri, *Trajectory Planning for
//!    Automatic Machines and Robots*, 2008, section 3.4; the bang-bang jerk
//!    profile is time-optimal for rest-to-rest motion under velocity,
//!    acceleration and jerk bounds), so the run's time is at least that of
//!    [`super::DoubleS`] over the length lower bound (less a relative
//!    rounding `ROUNDING` of its bisection). Step 4's envelopes let the
//!    acceleration change sign at the peak speed without passing through
//!    zero, so on a straight run this floor is the larger (100 mm at the
//!    thesis machine: 0.543 s, where steps 4-5 give 0.411 s).
//! 7. **The band's width at a turn** (`width.rs`). Let the window run from
//!    gate `a` to gate `b+1` with chord directions `u1` (chord `a`) and
//!    `u2` (chord `b`), `n = (u1 - u2) / |u1 - u2|`, `T` the unit tangent,
//!    `beta = pi/2 - angle(T, n)` (so `sin beta = n.T`) and `K` the
//!    supremum of the curvature over the window. Take a ball `B` (centre
//!    midway between the window's end gates, radius `r_B`) and `H` above
//!    `n.y` for every polyline point `y` within `r_B + e` of its centre
//!    (sampled, the sampling step added); then `h(x) = n.x - H <= e` on the
//!    band inside `B`. *Case A*: the path leaves `B` in the window; then
//!    its length there is at least `2 r_B` less the end gates' distances
//!    from the centre and radii, and the zone is bounded as in step 5 with
//!    that length. *Case B*: it stays in `B`. If
//!    `n.(q_b+1 - q_b) + rho_b + rho_b+1 < 0`, some point `s1` of
//!    `[tau_b, tau_b+1]` has `n.T < 0` (the mean of `n.T` there is
//!    negative). (i) `beta` is `K`-Lipschitz in arc length (the angle to a
//!    fixed point of the sphere is 1-Lipschitz, and `T` moves on it at
//!    rate `k`). (ii) For `s < s1` with `beta(s) > 0`, let `s*` be the
//!    first zero of `beta` after `s`; on `[s, s*]`,
//!    `beta >= beta(s) - K (x - s)` and `beta <= pi/2`, so
//!    `h(s*) - h(s) >= int_0^{beta(s)/K} sin(beta(s) - K t) dt =
//!    (1 - cos beta(s)) / K`, and `h(s*) <= e`: hence
//!    `sin beta(s) <= sqrt(2 K (e - h(s)))` (also when `beta(s) <= 0`).
//!    (iii) So `w = sqrt(e - h)` falls at most at `sqrt(K / 2)` per unit of
//!    arc length, at most `F sqrt(K / 2)` per second (a comparison
//!    argument, `w >= 0`). (iv) For gates `a <= i < j <= b`, `w` at
//!    `tau_i` is at least `sqrt(e - (n.q_i - H + rho_i))` and at `tau_j`
//!    at most `sqrt(e - (n.q_j - H - rho_j))`; their difference `G` takes
//!    at least `G / (F sqrt(K / 2))` s. (v) At the slowest point of the
//!    window (least speed `c`), the caps give `K <= A_n / c^2` and, with
//!    the jerk cap, `K <= sqrt(J / c^3)`; so the window takes at least
//!    `G / (F sqrt(K(c) / 2))` plus its chain lengths outside `[i, j]` at
//!    `F`, a bound increasing in `c`, used beside the rotation time of
//!    step 3. Time reversal gives the same for gates
//!    `a+1 <= i < j <= b+1` falling towards `q_j` when chord `a` rises.
//!    The zone takes the least of the two cases, and the largest over the
//!    balls. This argument bounds the window's time through its length at
//!    the feed: a path that weaves between the gates is not excluded by
//!    it, so it adds only some `G sqrt(2 / K) / F` (about 10 ms at a right
//!    angle on the thesis machine) and does not reach the speed cap
//!    `sqrt(A_n R)` of the largest radius that fits the band.
//! 8. **The tightest turn** (`tightest_turn`). For gates `i < j <= k < l`
//!    near a turn window, step 2 gives a least turn `alpha` of the tangent
//!    over `[tau_i, tau_l]`, and the path's positions at `tau_i` and
//!    `tau_l` are at most `D = |q_l - q_i| + rho_i + rho_l` apart. Let `L`
//!    be the path's length there and `K` its largest curvature. The turn
//!    needs `K L >= alpha`. If `L <= pi / K`, Schur's comparison theorem
//!    (a space curve of curvature at most `K` is no shorter in chord than
//!    the circular arc of curvature `K` and the same length, while that
//!    arc turns by at most `pi`; S. S. Chern, *Curves and surfaces in
//!    Euclidean space*, MAA Studies in Mathematics 4, 1967) puts its ends
//!    at least `(2 / K) sin(K L / 2) >= (2 / K) sin(alpha / 2)` apart, so
//!    `K >= k_need = 2 sin(alpha / 2) / D`. Otherwise `L > pi / K`. With
//!    least speed `c` in the window, the caps give `K <= K(c)` (step 7,
//!    (v)); so where `K(c) < k_need` the window is at least `pi / K(c)`
//!    long, and the zone is bounded as in step 5 with that length. Of the
//!    quadruples within a few gates of the window, the one with the
//!    largest `k_need` is used.
//! 9. **The corner's walls** (`walls.rs`). At the vertex `V = c(x)` of
//!    the window where the run turns most, with legs `u1` in and `u2`
//!    out, take the walls `n1` (outer normal of the first leg, away from
//!    the second), `n2` (of the second leg, away from the first) and
//!    `+-b` (`b = u1 x u2`, across the turn's plane). In a ball `B` of
//!    radius `R` around `V` every band point has `n . y <= H_n + e` (`H_n`
//!    the highest polyline point within `R + e`, as in step 7; for paths
//!    in order, of the run's stretch through `V` up to where it first
//!    leaves that ball: the path's points in `B` around where it passes
//!    `V` are matched to a connected stretch of the run through `V`
//!    within `R + e` of it, so a raster's neighbouring pass does not
//!    count). The path
//!    passes `x` at a point `p` within `e` of `c(x1)` and `c(x2)`, `x - r
//!    <= x1 <= x <= x2 <= x + r` (step 1; `p` within `e` of `V` for paths
//!    in order), so `w_n = e - (n . p - H_n) <= 2e + H_n - m_n` with `m_n`
//!    the larger of the least `n . c` over `[x - r, x]` and over `[x, x +
//!    r]`. If the path's curvature is at most `kappa` within arc length
//!    `S = pi / (2 kappa)` of `p`, and that arc stays in `B` (`S + e + r <=
//!    R`, the run's ends outside `B`), step 7 (ii) holds at `p` for each
//!    wall both ways along the path (the tangent's angle `beta` to the
//!    wall's plane falls at most at rate `kappa`, so the path rises
//!    `(1 - cos beta) / kappa` towards the wall within arc length `beta /
//!    kappa`): `1 - cos beta <= kappa w_n`, `sin beta = |n . T|`
//!    (step 7 (ii) before its last weakening). Averaged over the three
//!    walls (`1 - cos beta >= (n . T)^2 / 2`), `kappa >= lambda_min(sum n
//!    n^T / w_n) / 6`. **The fan** (`walls.rs`, `fan_walls`): every unit
//!    `nu` of the turn's plane with `nu . u1 >= 0` and `nu . u2 <= 0` is
//!    a wall too (both legs run no higher on it than the vertex), from
//!    `n1` to `n2` at most 30 degrees apart; so is each tilted across the
//!    plane, `nu' = cos psi nu +- sin psi b`, with `w(nu') <= 2e +
//!    sqrt((w_nu - 2e)^2 + E^2) = W_nu`, `E` the spread across the plane of
//!    the points `H` and `m` are taken over (a highest point is
//!    subadditive in `n`, a lowest superadditive, and `1 <= cos psi + sin
//!    psi`). With `T = cos chi t + sin chi b`, `t` in the plane, the tilt
//!    of the best `psi` and sign has `|nu' . T| = sqrt(cos^2 chi (nu .
//!    t)^2 + sin^2 chi) >= |nu . t|`; so for every direction `t` some wall
//!    has `1 - sqrt(1 - (nu . t)^2) <= kappa W_nu`, and `kappa` is at
//!    least the largest `K` at which the arcs of directions with `1 -
//!    sqrt(1 - (nu . t)^2) >= K W_nu` cover the plane's (bisection). `K_wall`
//!    is the larger of the two. At a right angle with every `w = 2e` the
//!    fan gives `(1 - cos 45 deg) / (2e) = 1 / (6.83 e)`, the curvature of
//!    the circle tangent to both outer walls through the band's inner
//!    corner (at a turn `theta`, `(1 - cos(theta / 2)) / (2e)` likewise up
//!    to 150 degrees): no circular turn is wider, so for them the cap is
//!    exact; the three walls gave `1 / (12 e)`. **The sweep**: followed
//!    only through a turn `gamma` of its tangent (arc length `gamma /
//!    kappa`), the path still rises `(cos(max(beta - gamma, 0)) - cos
//!    beta) / kappa` towards the wall, which grows with `beta`; the fan
//!    covers with that in place of `1 - cos beta`, and the arc `S` below
//!    is `gamma / kappa`. A right angle's worst tangent meets its walls at
//!    45 degrees, so an eighth of a turn proves what a quarter does, at
//!    half the reach. Of the sweeps `pi / 2`, `pi / 3`, `pi / 4` and `pi /
//!    6`, each corner gives two caps (`walls::Caps`): the lowest speed
//!    (the longest sweep that proves it), and the same speed (up to the
//!    bisection's rounding) at the shortest reach. So for every `kappa <
//!    K_wall` whose `S` fits, the curvature exceeds `kappa` within `S` of
//!    `p`, where the speed is then below that of `kappa` under the caps:
//!    the least speed of a window holding every path point within
//!    `S + e + r` of `V` is at most the speed of `K_wall` (a right
//!    angle's, about 13 mm/s on the thesis machine at 0.05 mm). The zone
//!    is bounded as in step 5 with that window and its least speed so
//!    capped.
//! 10. **The chain of slow points** (`chain.rs`). Steps 4-5 bound each
//!     zone on its own, with the speed free at zone boundaries, and let the
//!     acceleration jump from `+A` to `-A` at the top of a speed bump. The
//!     chain bounds the whole run at once. Take disjoint windows of gates,
//!     each holding a point `y_i` of speed at most a cap: step 9's walls
//!     (the nearest gates clear of the cap's reach outside the turn's
//!     window; for paths in order, the nearest either side of the vertex
//!     along the run: such a path passes the vertex after every gate
//!     before it, and the capped point lies on the stretch of path within
//!     the cap's reach of that passing, which no clear gate's ball
//!     touches), and for paths in order step 8's turns with both cases
//!     closed: a path in order stays within `e` of the run between the
//!     window's end gates, a set of
//!     diameter at most `Delta` (their arc length plus `2e`), and an arc
//!     of curvature at most `K` and length `pi / K` has its ends `2 / K`
//!     apart (Schur), so the long case has `K >= 2 / Delta` and the window
//!     holds curvature `min(k_need, 2 / Delta)`. The `y_i` are passed in
//!     order; the run's time is the sum over the links between them (the
//!     run's ends, at rest, included). In a link whose fastest point is
//!     inside, the acceleration is 0 there, at its speed `P`; the part
//!     before it takes at least the fastest rise from the link's start to
//!     `P` that never passes `P` (at the jerk limit to its top
//!     acceleration and back to 0, from the highest start allowed that
//!     does not overshoot), and covers at most that rise's distance plus
//!     `P` for the rest of its time, and mirrored after it. So the link
//!     takes at least `T1(P) + T2(P) + max(0, d - R1(P) - R2(P)) / P`, the
//!     least over `P` (branch and bound over ranges of `P`; rise times and
//!     distances grow with `P`): on a link from rest to rest, the
//!     double-S. A fastest point at an end keeps the speed under that
//!     end's cap, climbing to it from the other end no faster than the
//!     jerk and `A` allow. At each `y_i` the acceleration `a` is `>= 0`
//!     or `<= 0`, and `|a| <= sqrt(2 J cap)` (the speed changed by `a^2
//!     / (2 J)` within `|a| / J` of it and stays at least 0). Rising
//!     through `y_i`,
//!     the link after it starts with a rate of rise at most `a`, and in
//!     the link before it the speed falls into `y_i` (a rate of rise `-a`
//!     seen from inside); falling, the other way round. The range of `a`
//!     is cut into a few cells, each taken at its worst end. Each `y_i`
//!     lies in one of a few parts of its window (cut at gates), which
//!     bounds the links' lengths from below (the part itself is left
//!     out: the links on either side share it); the bound is the least
//!     over parts, signs and cells of `a` at every point (a dynamic
//!     programme along the chain). Any choice of
//!     windows bounds the run, but a point whose cap is high adds little
//!     and cuts the link it sits in (the speed there is only known to be
//!     under the cap), so several choices are tried: the walls' windows
//!     alone, the walls' with step 8's windows of caps below a quarter of
//!     the feed, and with those below half of it (`SCHUR_CAP_SHARES`:
//!     bumps of a few millimetres cap the speed between the two), each
//!     picked greedily by how fast a window's slow point could rise over
//!     half its length; and each with the corners' lowest caps and with
//!     their nearest (step 9, the sweep), the chain not being monotone in
//!     its windows.
//! 11. **Feeds, for paths in order.** Every step above takes the run's
//!     largest feed. A run may change feed along it (a plunge at the
//!     plunge feed, then the cut); `smooth` keeps each feed on its
//!     stretch (a piece that replaces several moves runs at the lowest of
//!     their feeds). Between consecutive gates the path is capped at the
//!     largest feed of the moves within a few tolerances of the stretch
//!     between them ([`InOrderGates::caps`];
//!     [`crate::verify::follows_in_order_within`] checks a path keeps to
//!     them), so between passing gates `i < j` it takes at least `(|q_j -
//!     q_i| - rho_i - rho_j)` over the largest cap between them; the best
//!     chain of such links bounds the run.
//! 12. **A reversal's tip, for paths in order** (`tip.rs`). A path in
//!     order passes the gates `a < b < c` next to a tip's gate `b` in
//!     order and stays within `e` of the run between `a` and `c`: up one
//!     leg and back down the other, inside a sleeve as wide as the band
//!     around them. Let `u` point from the midpoint of `q_a` and `q_c`
//!     to `q_b`, and `K` be the path's largest curvature there. If the
//!     stretch is no longer than `pi / K`, `h = u . x` rises by at least
//!     the tip's height over the outer gates less the radii, `H`, while
//!     `|h''| <= K` (`K L^2 >= 8 H`), and Schur's comparison (step 8)
//!     keeps the ends at most `D = |q_c - q_a| + rho_a + rho_c` apart:
//!     `asin(K D / 2)^2 >= 2 H K` or `K D >= 2`. Otherwise the tangent,
//!     which points up `u` on average before `b` and down it after, is
//!     across `u` at some point, and on one side of it an arc of length
//!     `pi / (2K)` advances at least `1 / K` across `u`, no more than the
//!     sleeve's width `W`: `K >= 1 / W`. On straight legs `W = 2e`, so
//!     the tip's window holds a speed of at most that of curvature `1 /
//!     (2e)` (5.8 mm/s on the thesis machine at 0.05 mm, where a U-turn
//!     of radius `e` inside the sleeve runs at 3.7). These windows join
//!     step 10's sets, and make a set of their own: the walls' windows
//!     between two tips, whose caps are far higher, weaken the chain
//!     there (see step 10).
//!
//! # Where it is loose
//! At a sharp turn, step 8 caps the slow point's speed through the gates
//! nearest the vertex (the nearest straight gates stand a few tolerances
//! from it, and their radii take some of the turn): a right angle's slow
//! point near 29 mm/s on the thesis machine at 0.05 mm. For paths in
//! order, step 9's fan caps it at the speed of the widest circular turn
//! inside the band, 13 mm/s, but only somewhere within about 0.3 mm of the
//! vertex (an eighth of a turn at that curvature, the sweep, and the
//! band); and a turn that is G2 must also bring its curvature up and down
//! again (`|dk/ds| v^3 <= J`, dropped here), which the corner methods' turns
//! pay at a peak curvature 3.6 times the circle's (about 5.5 mm/s; a right
//! angle between 2.5 mm legs at 0.05 mm). For paths in order, step 10
//! charges the climb to each
//! peak and back with the jerk-limited turn-round; for any path (where a
//! corner sharper than a right angle holds a bridge, and step 9 gives no
//! cap), steps 4-5 still let the acceleration reverse at once at the top
//! of a speed bump. A right angle between 50 mm legs is bounded at 0.720
//! s (0.833 s for paths in order), where the widest turn inside the band
//! plans in 0.931 s and `auto` writes 0.870 s (test
//! `the_widest_turn_inside_the_band_of_a_right_angle_takes_at_least_the_bound`).
//! On noise (`random_lines_0.001in.ngc`) no window turns by much more
//! than its gates' slack, and `auto` writes 2.6 times the bound
//! (docs/lower-bound.md).
//!
//! Every threshold is scaled from the tolerance: gate spacing, bridge
//! reach `r`, straightness `delta` and the flattening chord (a share of it).
//! So at a tolerance small against the run's turns (a fillet of hundreds
//! of tolerances) a window spans only part of a turn; a path within the
//! tolerance is within every wider one too, and the bound is also taken
//! at [`BoundOptions::wider`] times the tolerance, the largest kept
//! ([`lower_bound_time`]).

use super::limits::MachineLimits;
use super::plan::plan_rapid;
use super::program::Motion;
use super::{DoubleS, FeedError, Limits};
use crate::geom::Vec3;
use crate::math;
use crate::path::Piece;
use alloc::vec::Vec;

mod chain;
mod curved;
mod gates;
mod samples;
mod tip;
mod walls;
mod width;
use chain::{chain_time, pick_disjoint, schur_windows, SlowWindow, SCHUR_CAP_SHARES};
use gates::{chain_length, feed_caps, gates, polyline, tips_of, Gate};
pub use gates::{in_order_gates_of, InOrderGates};
use walls::Corner;
use width::{curvature_cap, rise, rise_time, GateHeight, Heights};

/// Which paths the bound holds for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BandPaths {
    /// Every path with each point within the tolerance of the run (the
    /// one-sided deviation [`crate::verify`] checks), its ends on the
    /// run's. Where the run comes back near itself (a closed contour, a
    /// raster of passes closer than twice the tolerance) such a path may
    /// cut across, and no gate can be placed there (step 1): on a closed
    /// contour the bound falls to the rest-to-rest floor of a run of
    /// length 0.
    #[default]
    Any,
    /// Paths that follow the run in order within the tolerance: some
    /// non-decreasing time `tau(s)` puts the path within the tolerance of
    /// `c(s)` for every `s` (Frechet distance at most the tolerance), as a
    /// tool that machines the whole contour does. Gates are then placed
    /// everywhere with radius `e` (step 1 becomes this assumption), also
    /// where the run comes back near itself.
    /// [`crate::verify::follows_in_order`] checks a path passes these gates
    /// in order, so the bound applies to it.
    InOrder,
}

/// How the bound is built; every length is a multiple of the tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundOptions {
    /// The band's half-width, mm.
    pub tolerance: f64,
    /// Which paths the bound holds for.
    pub paths: BandPaths,
    /// Spacing of candidate gates along the run, in tolerances.
    pub gate_spacing: f64,
    /// Arc length `r` within which gate pairs are local, in tolerances.
    pub reach: f64,
    /// Largest `delta` of a gate, in tolerances.
    pub straightness: f64,
    /// Flattening chord, as a share of the tolerance.
    pub chord_share: f64,
    /// Least turn `alpha` (rad) kept as a turn window.
    pub min_turn: f64,
    /// Longest window, in chords between gates.
    pub max_window: usize,
    /// Longest link of the chains that bound lengths, in gates.
    pub max_chain: usize,
    /// For paths in order: no gate stands where the run comes back within
    /// twice the band of it within this arc length, in tolerances (the
    /// tip of a sharp hairpin, which the corner methods cut; farther
    /// along, a raster's next pass or a stroke cut back, a gate stands).
    pub hairpin_reach: f64,
    /// For paths in order: a vertex where the run turns back on itself
    /// with a half-angle between its legs below this (rad) is a reversal
    /// whose tip every path in order passes (a gate on it), not a hairpin
    /// the corner methods cut: the corner methods' own threshold for the
    /// reversals they keep (`BsplineCornerOptions::min_half_angle`).
    pub reversal_half_angle: f64,
    /// ... and both its legs (the moves into and out of the tip) longer
    /// than this, in tolerances: the longest move the corner methods'
    /// absorbing may skip next to a sharp corner
    /// ([`crate::budget::SHORT_MOVE_SHARE`]), which cuts the tip of a
    /// reversal on such a leg (`Cereal.ngc`'s V-carve spikes dip 0.035
    /// mm at their tips and come back up).
    pub reversal_min_leg: f64,
    /// For paths in order: where the run is not straight enough for a
    /// straight gate, a gate of radius `e` stands on it if it turns by at
    /// most this (rad) over every stretch of twice the tolerance within
    /// the reach (a curve of radius above about `2e` over this); not at a
    /// sharper turn, whose vertex a corner method's cut passes farther
    /// than `e` (`curved.rs`). 0: straight gates only. Measurements:
    /// docs/tuning.md, `BoundOptions::curved_turn`.
    pub curved_turn: f64,
    /// ... and by at most this (rad) at each of its vertices there: a
    /// coarse polyline's vertex is a corner the corner methods cut, and a
    /// cut `h` deep passes the vertex at `h / cos(turn / 2)`.
    pub curved_vertex_turn: f64,
    /// Radii of the balls of the width argument (step 7), in tolerances.
    pub ball_radii: [f64; 2],
    /// Radii of the balls of the walls argument (step 9), in tolerances;
    /// at most the largest of `ball_radii`. Wide enough for a quarter turn
    /// at the walls' curvature, narrow enough to miss the rest of the run
    /// (measurements: docs/tuning.md, `BoundOptions::wall_radii`).
    pub wall_radii: [f64; 4],
    /// Multiples of the tolerance (above 1) at which the run is bounded
    /// too, the largest bound kept ([`lower_bound_time`]); others are
    /// skipped.
    pub wider: [f64; 2],
}

impl BoundOptions {
    /// The defaults at `tolerance` mm.
    pub fn new(tolerance: f64) -> BoundOptions {
        BoundOptions {
            tolerance,
            paths: BandPaths::Any,
            gate_spacing: 6.0,
            reach: 4.0,
            straightness: 0.5,
            chord_share: 1e-3,
            min_turn: 0.05,
            max_window: 6,
            max_chain: 48,
            hairpin_reach: 20.0,
            reversal_half_angle: 1e-6,
            reversal_min_leg: crate::budget::SHORT_MOVE_SHARE,
            curved_turn: 1.0,
            curved_vertex_turn: 0.2,
            ball_radii: [20.0, 100.0],
            wall_radii: [20.0, 30.0, 45.0, 70.0],
            wider: [4.0, 16.0],
        }
    }

    /// The tolerances the bound is taken at: the tolerance, then each of
    /// [`BoundOptions::wider`] times it (multiples not above 1 skipped).
    pub fn tolerances(&self) -> impl Iterator<Item = f64> + '_ {
        let tol = self.tolerance;
        core::iter::once(tol).chain(
            self.wider
                .iter()
                .filter(|k| k.is_finite() && **k > 1.0)
                .map(move |k| tol * k),
        )
    }
}

/// A lower bound and what it rests on.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LowerBound {
    /// Seconds.
    pub time: f64,
    /// Lower bound of the feed path's length, mm.
    pub length: f64,
    /// Turn windows used.
    pub turns: usize,
    /// Gates used (run ends included).
    pub gates: usize,
}

impl core::ops::AddAssign for LowerBound {
    fn add_assign(&mut self, o: LowerBound) {
        self.time += o.time;
        self.length += o.length;
        self.turns += o.turns;
        self.gates += o.gates;
    }
}

/// Why no bound could be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BoundError {
    #[error("tolerance must be a positive number, got {0}")]
    Tolerance(f64),
    #[error(transparent)]
    Feed(#[from] FeedError),
}

/// Speed grid of an envelope table: the rise from rest comes within a few
/// percent of exact (measurements: docs/tuning.md, `Envelope`,
/// `SPEED_NODES`).
const SPEED_NODES: usize = 512;
/// Cells of the grid over the least speed `c` of a window.
const C_CELLS: usize = 24;
/// Cells of the grid over the slow point's place in its window.
const P_CELLS: usize = 4;
/// Shares of a zone's side beyond its window over which step 5 splits
/// where the speed stops falling after the window's slowest point
/// (measurements: docs/tuning.md, `Rise::Valley` and `SPLIT_SHARES`).
const SPLIT_SHARES: [f64; 2] = [0.25, 1.0];
/// Relative rounding of the double-S time of step 6: its peak speed is
/// found by bisection to the last bit, the time a few ulps from exact.
const ROUNDING: f64 = 1e-12;
/// Most samples along a run (the bridge check, the band's heights; longer
/// runs are sampled more coarsely, the step added to each distance).
const MAX_SAMPLES: usize = 1 << 21;

/// How the speed may rise from an envelope's start point (module docs,
/// step 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Rise {
    /// The caps of every point of a run: `|a| <= A`, `a^2 <= 2 J (F - v)`
    /// and, every run starting and ending at rest, `a^2 <= 2 J v`.
    RunWide,
    /// From a point where the acceleration away from it is at most 0 (a
    /// speed minimum of a window, step 5): `a <= J t` after it, so along
    /// the fastest profile `a^2 <= 2 J (v - c)` besides the run-wide caps.
    Valley,
}

/// The fastest the speed can be at a distance from a point: from a speed
/// `c`, or from rest with zero acceleration (module docs, step 4).
///
/// Between nodes `speed[i - 1]` and `speed[i]` the acceleration is taken
/// at its largest there, `accel[i]` (the speed's square grows linearly
/// with distance at that rate), so `dist[i]` is a lower bound of the
/// distance needed to reach `speed[i]` and `time[i]` of the time: the
/// envelope is the profile of a piecewise-constant acceleration above the
/// true one, and its time over a distance, `dt = dv / a`, is exact for it.
struct Envelope {
    speed: Vec<f64>,
    accel: Vec<f64>,
    dist: Vec<f64>,
    time: Vec<f64>,
    feed: f64,
}

impl Envelope {
    fn new(c: f64, rise: Rise, f: f64, acc: f64, jerk: f64) -> Envelope {
        let c = c.clamp(0.0, f);
        let n = SPEED_NODES + 1;
        let mut e = Envelope {
            speed: Vec::with_capacity(n),
            accel: Vec::with_capacity(n),
            dist: Vec::with_capacity(n),
            time: Vec::with_capacity(n),
            feed: f,
        };
        e.speed.push(c);
        e.accel.push(0.0);
        e.dist.push(0.0);
        e.time.push(0.0);
        // The rising cap: from rest, or from the valley's speed `c`.
        let floor = match rise {
            Rise::RunWide => 0.0,
            Rise::Valley => c,
        };
        let g = |v: f64| {
            acc.min(math::sqrt(2.0 * jerk * (f - v).max(0.0)))
                .min(math::sqrt(2.0 * jerk * (v - floor).max(0.0)))
        };
        for i in 1..=SPEED_NODES {
            let u0 = e.speed[i - 1];
            // Nodes dense near `c`, where the speed changes fastest.
            let t = i as f64 / SPEED_NODES as f64;
            let u1 = c + (f - c) * t * t;
            // g rises with v up to (F + floor) / 2 and falls after: its
            // largest value on [u0, u1] is there, clamped into it.
            let gmax = g((0.5 * (f + floor)).clamp(u0, u1));
            // At constant acceleration: dx = (u1^2 - u0^2) / 2a, dt =
            // (u1 - u0) / a.
            let (dx, dt) = if gmax > 0.0 {
                (0.5 * (u1 - u0) * (u1 + u0) / gmax, (u1 - u0) / gmax)
            } else {
                (f64::INFINITY, f64::INFINITY)
            };
            e.speed.push(u1);
            e.accel.push(gmax);
            e.dist.push(e.dist[i - 1] + dx);
            e.time.push(e.time[i - 1] + dt);
        }
        e
    }

    /// An upper bound of the speed at distance `x` (at most the feed).
    fn at(&self, x: f64) -> f64 {
        let i = self.dist.partition_point(|&d| d <= x);
        if i >= self.speed.len() {
            return self.feed;
        }
        // On segment i: v^2 = u0^2 + 2 a (x - dist[i - 1]).
        let (u0, a) = (self.speed[i - 1], self.accel[i]);
        let v2 = u0 * u0 + 2.0 * a * (x - self.dist[i - 1]).max(0.0);
        math::sqrt(v2).min(self.speed[i])
    }

    /// A lower bound of the time to travel `x` at speeds at most
    /// [`Envelope::at`].
    fn time_to(&self, x: f64) -> f64 {
        if x <= 0.0 {
            return 0.0;
        }
        let i = self.dist.partition_point(|&d| d <= x);
        let last = self.speed.len() - 1;
        if i > last {
            return self.time[last] + (x - self.dist[last]) / self.feed;
        }
        let (u0, a) = (self.speed[i - 1], self.accel[i]);
        let dx = (x - self.dist[i - 1]).max(0.0);
        if !(a > 0.0 && a.is_finite()) {
            // No acceleration left (an envelope from the feed itself):
            // the speed stays at `u0`.
            return if u0 > 0.0 {
                self.time[i - 1] + dx / u0
            } else {
                f64::INFINITY
            };
        }
        let v = math::sqrt(u0 * u0 + 2.0 * a * dx);
        self.time[i - 1] + (v.min(self.speed[i]) - u0) / a
    }
}

/// Bisection steps for the meeting point of two envelopes: any split
/// gives a lower bound, and 16 steps put it within `2^-16` of the
/// stretch of the meeting point, at a third of the cost of 48 steps
/// (measurements: docs/tuning.md, `MEET_STEPS`).
const MEET_STEPS: usize = 16;

/// A lower bound of the time over `len` mm with the speed at distance `x`
/// at most `start.at(x)` and `end.at(len - x)` (`None`: free, the feed).
///
/// For any split `x*`, the time is at least the start envelope's time
/// over `[0, x*]` plus the end envelope's over `[x*, len]` (each bounds
/// the speed everywhere); the split where they meet gives the largest.
fn stretch_time(len: f64, f: f64, start: Option<&Envelope>, end: Option<&Envelope>) -> f64 {
    if len <= 0.0 {
        return 0.0;
    }
    let speed = |e: Option<&Envelope>, x: f64| e.map_or(f, |e| e.at(x)).min(f);
    let time = |e: Option<&Envelope>, x: f64| e.map_or(x / f, |e| e.time_to(x));
    // The meeting point: the start's speed rises with x, the end's falls.
    let (mut lo, mut hi) = (0.0, len);
    for _ in 0..MEET_STEPS {
        let mid = 0.5 * (lo + hi);
        if speed(start, mid) < speed(end, len - mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let x = 0.5 * (lo + hi);
    time(start, x) + time(end, len - x)
}

/// The least turn of the tangent of a band path between its mean
/// directions over the gate pairs `first` and `second` (passed in this
/// order; step 2): the chords' angle less each chord's slack
/// `asin((rho_i + rho_j) / |q_j - q_i|)`. `None` where a chord is no
/// longer than its gates' radii.
fn turn_between(gates: &[Gate], first: (usize, usize), second: (usize, usize)) -> Option<f64> {
    let chord = |(i, j): (usize, usize)| {
        let d = gates[j].at - gates[i].at;
        let (len, rad) = (d.norm(), gates[i].radius + gates[j].radius);
        if len > rad {
            Some((d.normalized(0.0)?, asin(rad / len)))
        } else {
            None
        }
    };
    let (u1, s1) = chord(first)?;
    let (u2, s2) = chord(second)?;
    Some(u1.angle_to(u2) - s1 - s2)
}

/// A turn of step 8: gate pairs `first` and `second` passed in order, the
/// least turn `alpha` of the tangent between their mean directions, and
/// the curvature `k_need` the window from `first.0` to `second.1` reaches
/// somewhere unless its length exceeds `pi / K` (`K` its largest
/// curvature).
#[derive(Clone, Copy, Debug)]
struct TightTurn {
    first: (usize, usize),
    second: (usize, usize),
    alpha: f64,
    k_need: f64,
}

/// The turn of step 8 between the gate pairs `first` and `second`
/// (passed in this order), or `None` where it turns by less than
/// `min_turn`: the least turn `alpha` of the tangent between their mean
/// directions ([`turn_between`]) and the curvature `k_need = 2 sin(alpha
/// / 2) / D` the stretch reaches unless it is longer than `pi / K`, with
/// `D = |q_l - q_i| + rho_i + rho_l` the most its ends can be apart.
fn schur_turn(
    gates: &[Gate],
    first: (usize, usize),
    second: (usize, usize),
    min_turn: f64,
) -> Option<TightTurn> {
    let alpha = turn_between(gates, first, second)?;
    if alpha < min_turn {
        return None;
    }
    let (i, l) = (first.0, second.1);
    let d = gates[l].at.dist(gates[i].at) + gates[i].radius + gates[l].radius;
    if d <= 0.0 {
        return None;
    }
    let k_need = 2.0 * math::sin(0.5 * alpha.min(core::f64::consts::PI)) / d;
    Some(TightTurn {
        first,
        second,
        alpha,
        k_need,
    })
}

/// Gates searched on each side of a turn window for step 8, and the
/// longest end chord, in gates (measurements: docs/tuning.md,
/// `SCHUR_SPREAD`).
const SCHUR_SPREAD: usize = 4;

/// The turn of step 8 with the largest `k_need` among gate quadruples
/// `i < j <= k < l` within `SCHUR_SPREAD` gates of the turn window
/// `window` (gate indices) and inside `zone`: a path that turns by `alpha`
/// over an arc of length `L <= pi / K` with curvature at most `K` has its
/// ends at least `(2 / K) sin(K L / 2) >= (2 / K) sin(alpha / 2)` apart
/// (Schur's comparison theorem for space curves against a circular arc;
/// S. S. Chern, *Curves and surfaces in Euclidean space*, 1967), and the
/// ends of the window are at most `D = |q_l - q_i| + rho_i + rho_l` apart;
/// so `K >= 2 sin(alpha / 2) / D` or `L > pi / K`.
fn tightest_turn(
    gates: &[Gate],
    window: (usize, usize),
    zone: (usize, usize),
    opts: &BoundOptions,
) -> Option<TightTurn> {
    let lo = window.0.saturating_sub(SCHUR_SPREAD).max(zone.0);
    let hi = (window.1 + SCHUR_SPREAD).min(zone.1);
    let mut best: Option<TightTurn> = None;
    for j in lo + 1..=hi {
        for k in j..hi {
            for i in j.saturating_sub(SCHUR_SPREAD).max(lo)..j {
                for l in k + 1..=(k + SCHUR_SPREAD).min(hi) {
                    if let Some(t) = schur_turn(gates, (i, j), (k, l), opts.min_turn) {
                        if best.is_none_or(|b| t.k_need > b.k_need) {
                            best = Some(t);
                        }
                    }
                }
            }
        }
    }
    best
}

/// The polyline vertex strictly between arc lengths `lo` and `hi` where
/// the run turns the most (its arc length), or `None`.
fn sharpest_vertex(pts: &[Vec3], s: &[f64], lo: f64, hi: f64) -> Option<f64> {
    let a = s.partition_point(|&v| v <= lo).max(1);
    let b = s.partition_point(|&v| v < hi).min(pts.len() - 1);
    let mut best: Option<(f64, f64)> = None;
    for i in a..b {
        let turn = (pts[i] - pts[i - 1]).angle_to(pts[i + 1] - pts[i]);
        if best.is_none_or(|(t, _)| turn > t) {
            best = Some((turn, s[i]));
        }
    }
    best.map(|(_, x)| x)
}

/// `asin(x)` for `x` in `[0, 1]`.
fn asin(x: f64) -> f64 {
    math::atan2(x, math::sqrt((1.0 - x * x).max(0.0)))
}

/// A lower bound of the time of any path within `opts.tolerance` of the
/// run `pieces`, planned under `m` (module docs). `override_feed`: every
/// move at the machine's maximum feed, as the planner's option.
///
/// The largest of the bounds at the tolerance and at each of
/// [`BoundOptions::wider`] times it: a path within the tolerance of the
/// run (in order, for [`BandPaths::InOrder`]: Frechet distance at most
/// the tolerance) is within every wider one, so each bound holds for it.
/// Every length of the argument is a multiple of the tolerance (gate
/// spacing, windows, balls), so at a tolerance small against the run's
/// turns a window spans only part of a turn, and a wider tolerance can
/// bound more: a 30 x 20 mm rectangle with G3 fillets of radius 0.92 mm
/// at 100 mm/s is bounded in order at 1.118 s at 0.005 mm and 1.244 s at
/// 0.02 mm on the thesis machine (test
/// `regression_fillet_radius_a_small_tolerance_bounds_no_less_than_a_wider_one`;
/// docs/tuning.md, `BoundOptions::wider`).
pub fn lower_bound_time(
    pieces: &[Piece],
    opts: &BoundOptions,
    m: &MachineLimits,
    override_feed: bool,
) -> Result<LowerBound, BoundError> {
    let tol = opts.tolerance;
    if !(tol.is_finite() && tol > 0.0) {
        return Err(BoundError::Tolerance(tol));
    }
    m.validate().map_err(|l| FeedError::BadLimit {
        name: l.name,
        value: l.value,
    })?;
    let mut best: Option<LowerBound> = None;
    for tolerance in opts.tolerances() {
        let b = bound_at(
            pieces,
            &BoundOptions { tolerance, ..*opts },
            m,
            override_feed,
        )?;
        if best.is_none_or(|w| b.time > w.time) {
            best = Some(b);
        }
    }
    let mut best = best.unwrap_or_default();
    best.time *= 1.0 - PLAN_ACCURACY;
    Ok(best)
}

/// Relative share by which the planner's plans may fall below the model
/// the bound bounds (module docs): the bound is lowered by it. The
/// look-ahead over many joints can run a few parts in a million faster
/// than one rest-to-rest double-S: LinuxCNC's
/// `zigzag_0.002_0.0005.ngc` as `smooth` writes it at 0.05 mm (ten
/// near-collinear G1 lines, 101.600004 mm) plans in 1.0915254 s, where
/// the double-S over its 101.600001 mm chord takes 1.0915272 s (1.6 parts
/// in a million less), which the bound at 16 times the tolerance reached
/// (docs/tuning.md, `BoundOptions::wider`).
const PLAN_ACCURACY: f64 = 1e-5;

/// [`lower_bound_time`] at `opts.tolerance` alone, `m` validated.
///
/// For paths in order, the larger of the bounds with and without the
/// gates of the run's reversals (step 1): those gates are added to the
/// others, so a path that passes them all passes either set, but the
/// turn windows are picked greedily over the chords between gates, and a
/// short chord next to a tip can break a window the set without it had
/// (measurements: docs/tuning.md, "Gates on reversals' tips"). The
/// curved gates can do the same, by a tenth of a percent on a few runs;
/// the bound without them is not taken too, which would double the
/// in-order bound's cost (docs/tuning.md, `BoundOptions::curved_turn`).
fn bound_at(
    pieces: &[Piece],
    opts: &BoundOptions,
    m: &MachineLimits,
    override_feed: bool,
) -> Result<LowerBound, BoundError> {
    let tol = opts.tolerance;
    let speeds: Vec<f64> = pieces
        .iter()
        .map(|p| piece_speed(p, m, override_feed))
        .collect();
    let f = speeds.iter().fold(0.0f64, |a, &b| a.max(b));
    if pieces.is_empty() || f <= 0.0 {
        return Ok(LowerBound::default());
    }
    let chord = tol * opts.chord_share;
    let (pts, s, ends) = polyline(pieces, chord);
    if pts.len() < 2 {
        return Ok(LowerBound::default());
    }
    let run = RunPolyline {
        pts: &pts,
        s: &s,
        ends: &ends,
        speeds: &speeds,
        feed: f,
    };
    let tips = tips_of(&pts, &s, opts);
    let with = bound_over_gates(&run, &tips, opts, m)?;
    if tips.is_empty() {
        return Ok(with);
    }
    let other = bound_over_gates(&run, &[], opts, m)?;
    Ok(if other.time > with.time { other } else { with })
}

/// A run as the bound sees it: its polyline (points `pts` at arc lengths
/// `s`), the arc length at which each piece ends, each piece's speed and
/// the largest (`feed`, mm/s).
struct RunPolyline<'a> {
    pts: &'a [Vec3],
    s: &'a [f64],
    ends: &'a [f64],
    speeds: &'a [f64],
    feed: f64,
}

/// [`lower_bound_time`] of `run` over the gates `opts` puts on it, with
/// gates on the reversals' tips `tips`.
fn bound_over_gates(
    run: &RunPolyline,
    tips: &[(f64, Vec3)],
    opts: &BoundOptions,
    m: &MachineLimits,
) -> Result<LowerBound, BoundError> {
    let (pts, s, ends, speeds, f) = (run.pts, run.s, run.ends, run.speeds, run.feed);
    let tol = opts.tolerance;
    // The tangential limits of steps 6 and 10.
    let lim = Limits::new(f, m.acc, m.jerk)?;
    let chord = tol * opts.chord_share;
    let e = tol + chord;
    let (gates, bridges) = gates(pts, s, e, opts, tips);
    // The largest ball of steps 7 and 9.
    let rmax = opts.ball_radii.iter().fold(0.0f64, |a, &b| a.max(b)) * tol;
    let heights = {
        let total = *s.last().unwrap_or(&0.0);
        let step = (0.5 * e).max(total / MAX_SAMPLES as f64);
        Heights::new(pts, s, step, rmax + e + step)
    };
    // Chords between consecutive gates: length lower bound, direction,
    // angular slack.
    let chords: Vec<(f64, Option<Vec3>, f64)> = gates
        .windows(2)
        .map(|w| {
            let d = w[1].at - w[0].at;
            let len = d.norm();
            let rad = w[0].radius + w[1].radius;
            let dir = if len > rad { d.normalized(0.0) } else { None };
            (
                (len - rad).max(0.0),
                dir,
                if len > rad { asin(rad / len) } else { 0.0 },
            )
        })
        .collect();
    // Turn windows: chord a to chord b, disjoint, in order.
    let mut windows: Vec<(usize, usize, f64)> = Vec::new();
    let mut i = 0;
    while i < chords.len() {
        let mut best: Option<(usize, f64)> = None;
        if let (_, Some(ui), si) = chords[i] {
            for (j, cj) in chords
                .iter()
                .enumerate()
                .take((i + opts.max_window + 1).min(chords.len()))
                .skip(i + 1)
            {
                if let (_, Some(uj), sj) = *cj {
                    let alpha = ui.angle_to(uj) - si - sj;
                    if alpha >= opts.min_turn && best.is_none_or(|(_, b)| alpha > b) {
                        best = Some((j, alpha));
                    }
                }
            }
        }
        match best {
            Some((j, alpha)) => {
                windows.push((i, j, alpha));
                i = j + 1;
            }
            None => i += 1,
        }
    }
    // Length between gate a and gate b: the longest chain of gates
    // between them (each link `|q_i - q_j| - rho_i - rho_j`), which loses
    // the gates' radii only where the chain turns.
    let chord_sum = |a: usize, b: usize| chain_length(&gates, a, b, opts.max_chain);
    let length = chord_sum(0, chords.len());
    let rest = Envelope::new(0.0, Rise::RunWide, f, m.acc, m.jerk);
    let mut time = 0.0;
    if windows.is_empty() {
        time = stretch_time(length, f, Some(&rest), Some(&rest));
    } else {
        let cs: Vec<f64> = (0..=C_CELLS)
            .map(|k| f * (k as f64 / C_CELLS as f64) * (k as f64 / C_CELLS as f64))
            .collect();
        let envs: Vec<Envelope> = cs
            .iter()
            .map(|&c| Envelope::new(c, Rise::RunWide, f, m.acc, m.jerk))
            .collect();
        let valleys: Vec<Envelope> = cs
            .iter()
            .map(|&c| Envelope::new(c, Rise::Valley, f, m.acc, m.jerk))
            .collect();
        let jerk = m.jerk_on_curves.then_some(m.jerk);
        let corner = Corner {
            pts,
            s,
            e,
            reach: match opts.paths {
                BandPaths::Any => opts.reach * tol,
                BandPaths::InOrder => 0.0,
            },
            bridges: bridges.as_ref(),
            heights: &heights,
        };
        let wall_radii: Vec<f64> = opts
            .wall_radii
            .iter()
            .map(|&rb| rb * tol)
            .filter(|&rb| rb <= rmax)
            .collect();
        // The fastest a curvature can be run: `k v^2 <= A_n`, and with the
        // jerk cap `k^2 v^3 <= J`.
        let speed_of = |k: f64| {
            let mut v = math::sqrt(m.normal_acc / k);
            if m.jerk_on_curves {
                v = v.min(math::cbrt(m.jerk / (k * k)));
            }
            v
        };
        // Step 10's slow windows, from step 9's caps.
        let mut slow: Vec<SlowWindow> = Vec::new();
        // The same with each corner's nearest cap (`walls::Caps`).
        let mut slow_near: Vec<SlowWindow> = Vec::new();
        // Zone boundaries: the chord index where each zone starts.
        let mut zone_start = 0;
        for (w, &(a, b, alpha)) in windows.iter().enumerate() {
            let zone_end = match windows.get(w + 1) {
                Some(&(next_a, _, _)) => (b + 1 + next_a) / 2,
                None => chords.len(),
            };
            let left = chord_sum(zone_start, a);
            let win = chord_sum(a, b + 1);
            let right = chord_sum(b + 1, zone_end);
            let start_env = (zone_start == 0).then_some(&rest);
            let end_env = (zone_end == chords.len()).then_some(&rest);
            // The zone's time with the turn `alpha` in a window of length
            // `win` between `left` and `right` (steps 3-5), and the width
            // cap of step 7 (`cap`, 0 for none).
            let zone_time = |left: f64,
                             win: f64,
                             right: f64,
                             alpha: f64,
                             cap: &dyn Fn(f64) -> f64,
                             k_need: f64,
                             k_long: f64,
                             c_max: f64| {
                let p_time = |k: usize, win: f64| {
                    let (wide, valley) = (&envs[k], &valleys[k]);
                    // `k` is the upper end of the cell of `c`.
                    let c_hi = cs[k];
                    let total = left + win + right;
                    // The slow point `P` (least speed of the window) with
                    // the envelope `before` towards the zone's start and
                    // `after` towards its end, somewhere in a span `span`
                    // long after `lead` of the zone: each cell of places
                    // bounded by its ends, the zone being at least its
                    // cell's width longer than that.
                    let slow_in = |lead: f64,
                                   span: f64,
                                   cells: usize,
                                   before: &Envelope,
                                   after: &Envelope| {
                        (0..cells)
                            .map(|pc| {
                                let y0 = lead + span * pc as f64 / cells as f64;
                                let y1 = lead + span * (pc + 1) as f64 / cells as f64;
                                stretch_time(y0, f, start_env, Some(before))
                                    + stretch_time(total - y1, f, Some(after), end_env)
                                    + (y1 - y0) / f
                            })
                            .fold(f64::INFINITY, f64::min)
                    };
                    // Inside the window the speed's minimum has a = 0.
                    let inside = slow_in(left, win, P_CELLS, valley, valley);
                    // At the window's end the speed does not rise at `P`
                    // (a valley after it, the run-wide caps before it);
                    // it goes on falling to the next zero `m` of the
                    // acceleration. For a distance `d`: either `m` is
                    // within `d` after `P` (a valley both ways there), or
                    // the speed is at most `c` for `d` after `P` and still
                    // falling there (a valley after that point). The same
                    // mirrored at the window's start.
                    let below_c = |len: f64| {
                        if c_hi > 0.0 {
                            len / c_hi
                        } else {
                            f64::INFINITY
                        }
                    };
                    let mut at_end = slow_in(left + win, 0.0, 1, wide, valley);
                    let mut at_start = slow_in(left, 0.0, 1, valley, wide);
                    for share in SPLIT_SHARES {
                        let d = right * share;
                        let near = slow_in(left + win, d, 2, valley, valley);
                        let far = stretch_time(left + win, f, start_env, Some(wide))
                            + below_c(d)
                            + stretch_time(right - d, f, Some(valley), end_env);
                        at_end = at_end.max(near.min(far));
                        let d = left * share;
                        let near = slow_in(left - d, d, 2, valley, valley);
                        let far = stretch_time(left - d, f, start_env, Some(valley))
                            + below_c(d)
                            + stretch_time(win + right, f, Some(wide), end_env);
                        at_start = at_start.max(near.min(far));
                    }
                    inside.min(at_start).min(at_end)
                };
                let rot = |c: f64, win: f64| {
                    let mut per = c / m.normal_acc;
                    if m.jerk_on_curves {
                        per = per.max(math::sqrt(c / m.jerk));
                    }
                    (alpha * per).max(cap(c)).max(win / f) + (left + right) / f
                };
                (0..C_CELLS)
                    .map(|k| {
                        // Step 9: the window's least speed is at most
                        // `c_max`.
                        if cs[k] > c_max {
                            return f64::INFINITY;
                        }
                        // Step 8: a window whose every speed is at least
                        // `cs[k]` has curvature at most `kc`; below
                        // `k_need` it is longer than `pi / kc`, which
                        // for paths in order takes `kc >= k_long`.
                        let kc = curvature_cap(cs[k], m.normal_acc, jerk);
                        let win = if kc < k_need {
                            if kc < k_long {
                                return f64::INFINITY;
                            }
                            win.max(core::f64::consts::PI / kc)
                        } else {
                            win
                        };
                        p_time(k + 1, win).max(rot(cs[k], win))
                    })
                    .fold(f64::INFINITY, f64::min)
            };
            let mut zone = zone_time(left, win, right, alpha, &|_| 0.0, 0.0, 0.0, f64::INFINITY);
            // Step 8: the tightest turn near the window (Schur's
            // comparison), a window of its own in the zone.
            if let Some(t) = tightest_turn(&gates, (a, b + 1), (zone_start, zone_end), opts) {
                let (left, win, right) = (
                    chord_sum(zone_start, t.first.0),
                    chord_sum(t.first.0, t.second.1),
                    chord_sum(t.second.1, zone_end),
                );
                // Paths in order stay within `e` of the run between the
                // window's end gates, a set of diameter at most `Delta`;
                // an arc of curvature at most `K` and length `pi / K`
                // has its ends `2 / K` apart, so a long window has `K >=
                // 2 / Delta`.
                let k_long = match opts.paths {
                    BandPaths::InOrder => {
                        2.0 / (gates[t.second.1].along - gates[t.first.0].along + 2.0 * e)
                    }
                    BandPaths::Any => 0.0,
                };
                zone = zone.max(zone_time(
                    left,
                    win,
                    right,
                    t.alpha,
                    &|_| 0.0,
                    t.k_need,
                    k_long,
                    f64::INFINITY,
                ));
            }
            // Step 9: the corner's walls cap the speed near its sharpest
            // vertex, in a window of gates beyond the cap's ball.
            let vertex = sharpest_vertex(pts, s, gates[a].along, gates[b + 1].along);
            let wall = vertex.and_then(|x| corner.cap(x, &wall_radii, speed_of));
            if let (Some(caps), Some(x)) = (wall, vertex) {
                // Step 10's slow window: the nearest gates clear of the
                // cap's reach outside the turn's window, anywhere along
                // the run; for paths in order, the nearest either side of
                // the vertex (module docs, step 10).
                let (before, after) = if opts.paths == BandPaths::InOrder {
                    let next = gates.partition_point(|g| g.along <= x);
                    (next, next)
                } else {
                    (a + 1, b + 1)
                };
                for (w, into) in [(caps.slowest, &mut slow), (caps.nearest, &mut slow_near)] {
                    let clear = |g: usize| gates[g].at.dist(w.at) > w.reach + gates[g].radius;
                    let i = (0..before).rev().find(|&g| clear(g));
                    let l = (after..gates.len()).find(|&g| clear(g));
                    if let (Some(first), Some(last)) = (i, l) {
                        into.push(SlowWindow {
                            first,
                            last,
                            cap: w.speed,
                        });
                    }
                }
            }
            if let Some(w) = wall.map(|c| c.slowest) {
                let clear = |g: usize| gates[g].at.dist(w.at) > w.reach + gates[g].radius;
                let i = (zone_start..=a).rev().find(|&g| clear(g));
                let l = (b + 1..=zone_end).find(|&g| clear(g));
                if let (Some(i), Some(l)) = (i, l) {
                    let alpha = if l > i + 1 {
                        turn_between(&gates, (i, i + 1), (l - 1, l)).unwrap_or(0.0)
                    } else {
                        0.0
                    };
                    zone = zone.max(zone_time(
                        chord_sum(zone_start, i),
                        chord_sum(i, l),
                        chord_sum(l, zone_end),
                        alpha.max(0.0),
                        &|_| 0.0,
                        0.0,
                        0.0,
                        w.speed,
                    ));
                }
            }
            // Step 7: the band's width at the turn, in a ball of each
            // radius; outside the ball the window is long (case A).
            let (qa, qb) = (gates[a], gates[b + 1]);
            let n = match (chords[a].1, chords[b].1) {
                (Some(u1), Some(u2)) => (u1 - u2).normalized(tol * 1e-6),
                _ => None,
            };
            if let Some(n) = n {
                let mid = (qa.at + qb.at) * 0.5;
                let goes_down =
                    n.dot(gates[b + 1].at - gates[b].at) + gates[b].radius + gates[b + 1].radius
                        < 0.0;
                let comes_up =
                    n.dot(gates[a + 1].at - gates[a].at) - gates[a].radius - gates[a + 1].radius
                        > 0.0;
                for &rb in &opts.ball_radii {
                    let rb = rb * tol;
                    let top = heights.top(mid, rb + e, n);
                    let gh = |g: usize| GateHeight {
                        height: n.dot(gates[g].at) - top,
                        radius: gates[g].radius,
                    };
                    // (rise G, chain length of the window outside it).
                    let mut rises: Vec<(f64, f64)> = Vec::new();
                    for i in a..=b + 1 {
                        for j in i + 1..=b + 1 {
                            let g = if j <= b && goes_down {
                                rise(e, gh(i), gh(j))
                            } else {
                                0.0
                            };
                            let g_rev = if i > a && comes_up {
                                rise(e, gh(j), gh(i))
                            } else {
                                0.0
                            };
                            let g = g.max(g_rev);
                            if g > 0.0 {
                                rises.push((g, chord_sum(a, i) + chord_sum(j, b + 1)));
                            }
                        }
                    }
                    if rises.is_empty() {
                        continue;
                    }
                    let cap = |c: f64| {
                        let k = curvature_cap(c, m.normal_acc, jerk);
                        rises
                            .iter()
                            .map(|&(g, rest)| rise_time(g, f, k) + rest / f)
                            .fold(0.0, f64::max)
                    };
                    let inside = zone_time(left, win, right, alpha, &cap, 0.0, 0.0, f64::INFINITY);
                    let long = 2.0 * rb - qa.at.dist(mid) - qb.at.dist(mid) - qa.radius - qb.radius;
                    let outside = zone_time(
                        left,
                        win.max(long),
                        right,
                        alpha,
                        &|_| 0.0,
                        0.0,
                        0.0,
                        f64::INFINITY,
                    );
                    zone = zone.max(inside.min(outside));
                }
            }
            time += zone;
            zone_start = zone_end;
        }
        // Step 12: for paths in order, the slow point at each reversal's
        // tip.
        let at_tips = if opts.paths == BandPaths::InOrder {
            tip::tip_windows(&gates, tips, pts, s, e, speed_of)
        } else {
            Vec::new()
        };
        slow.extend(at_tips.iter().copied());
        slow_near.extend(at_tips.iter().copied());
        // Step 10: the chain of slow points over the whole run.
        // Any choice of slow windows bounds the run; a slow point with a
        // high cap may weaken the chain (the speed there is only known
        // to be under it), so the walls' alone are tried too.
        // Each corner's two caps give two sets of windows, each tried.
        let along = |a: usize, b: usize| gates[b].along - gates[a].along;
        // Step 8's windows up to the highest share (the last), each
        // share's taken from them.
        let top_share = SCHUR_CAP_SHARES[SCHUR_CAP_SHARES.len() - 1];
        let schur = if opts.paths == BandPaths::InOrder {
            schur_windows(&gates, e, opts.min_turn, speed_of, f, top_share)
        } else {
            Vec::new()
        };
        // Where every corner's two caps give the same windows, once.
        let mut sets = if slow_near == slow {
            alloc::vec![slow]
        } else {
            alloc::vec![slow, slow_near]
        };
        if !at_tips.is_empty() {
            sets.push(at_tips);
        }
        for slow in sets {
            let walls = pick_disjoint(slow.clone(), along, m.jerk);
            time = time.max(chain_time(walls, chords.len(), chord_sum, lim));
            if opts.paths == BandPaths::InOrder {
                // The shares ascend, so their sets are nested: one that
                // adds no window to the one before is the same chain.
                let mut taken = None;
                for share in SCHUR_CAP_SHARES {
                    let below: Vec<SlowWindow> = schur
                        .iter()
                        .filter(|w| w.cap < share * f)
                        .copied()
                        .collect();
                    if taken == Some(below.len()) {
                        continue;
                    }
                    taken = Some(below.len());
                    let mut with = slow.clone();
                    with.extend(below);
                    let with = pick_disjoint(with, along, m.jerk);
                    time = time.max(chain_time(with, chords.len(), chord_sum, lim));
                }
            }
        }
    }
    // Step 11: for paths in order, each stretch between gates at its
    // feed.
    if opts.paths == BandPaths::InOrder {
        let caps = feed_caps(&gates, ends, speeds, tol);
        time = time.max(feed_floor(&gates, &caps, opts.max_chain));
    }
    // Step 6: the rest-to-rest double-S over the run's length.
    if length > 0.0 {
        let ds = DoubleS::plan(length, 0.0, 0.0, &lim)?;
        time = time.max(ds.duration() * (1.0 - ROUNDING));
    }
    Ok(LowerBound {
        time,
        length,
        turns: windows.len(),
        gates: gates.len(),
    })
}

/// Step 11: a lower bound of the time of a path in order that runs no
/// faster than `caps[i]` between passing gates `i` and `i + 1`: between
/// passing gates `i < j` (at most `max_link` apart) it covers at least
/// `|q_j - q_i| - rho_i - rho_j` no faster than the highest cap between
/// them; the best chain of such links ([`gates::best_chain`]).
fn feed_floor(gates: &[Gate], caps: &[f64], max_link: usize) -> f64 {
    let last = gates.len().saturating_sub(1);
    gates::best_chain(gates, 0, last, max_link, |i, j, link| {
        let cap = caps[i..j].iter().fold(0.0f64, |m, &c| m.max(c));
        if cap > 0.0 {
            link / cap
        } else {
            0.0
        }
    })
}

/// The speed (mm/s) the planner runs a piece at most: its programmed
/// feed, or the machine's where none is programmed or with
/// `override_feed`, never above the machine's.
pub fn piece_speed(p: &Piece, m: &MachineLimits, override_feed: bool) -> f64 {
    if override_feed {
        m.max_feed
    } else {
        p.feed
            .map(|v| v / 60.0)
            .unwrap_or(m.max_feed)
            .min(m.max_feed)
    }
}

/// [`lower_bound_time`] over a program's motions: every run bounded,
/// every rapid timed as the planner times it (rest to rest at the
/// machine's limits).
pub fn program_lower_bound(
    motions: &[Motion],
    opts: &BoundOptions,
    m: &MachineLimits,
    override_feed: bool,
) -> Result<LowerBound, BoundError> {
    let mut total = LowerBound::default();
    for mo in motions {
        match mo {
            Motion::Feed(run) => total += lower_bound_time(&run.pieces, opts, m, override_feed)?,
            Motion::Rapid(p) => {
                let len = p.curve.length(opts.tolerance * opts.chord_share);
                if len > 0.0 && len.is_finite() {
                    total.time += plan_rapid(len, m)?.duration();
                }
            }
        }
    }
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The thesis machine's feed, acceleration and jerk.
    const F: f64 = 400.0;
    const A: f64 = 4000.0;
    const J: f64 = 20000.0;

    #[test]
    fn rest_to_rest_stretch_time_is_the_jerk_limited_rise_within_three_percent() {
        // Below F / 2 and A, the envelopes from rest are the profile of
        // jerk J from rest (a = sqrt(2 J v)), meeting in the middle: each
        // half takes (6 (L / 2) / J)^(1/3).
        let rest = Envelope::new(0.0, Rise::RunWide, F, A, J);
        for len in [0.5, 2.0, 8.0] {
            let exact = 2.0 * math::cbrt(3.0 * len / J);
            assert!(exact * J * exact / 8.0 < 0.5 * F, "{len}: rises past F / 2");
            let t = stretch_time(len, F, Some(&rest), Some(&rest));
            assert!(t <= exact * (1.0 + 1e-12), "{len}: {t} above {exact}");
            assert!(t >= 0.97 * exact, "{len}: {t} loose against {exact}");
        }
    }

    #[test]
    fn an_envelope_from_the_feed_runs_at_the_feed() {
        // Regression: an envelope whose start speed is the feed has no
        // acceleration left; its time to a distance was infinite, which
        // made a window's top cell of least speeds look impossible.
        for rise in [Rise::RunWide, Rise::Valley] {
            let env = Envelope::new(F, rise, F, A, J);
            assert!((env.time_to(10.0) - 10.0 / F).abs() < 1e-12);
            assert_eq!(env.at(10.0), F);
            let t = stretch_time(10.0, F, Some(&env), None);
            assert!((t - 10.0 / F).abs() < 1e-12, "{t}");
        }
    }

    #[test]
    fn an_envelope_is_above_every_constant_jerk_rise() {
        // From speed c with zero acceleration, jerk J until F / 2: the
        // speed at each distance stays below the envelope, and the time to
        // each distance above the envelope's.
        for c in [0.0, 5.0, 50.0] {
            let env = Envelope::new(c, Rise::Valley, F, A, J);
            let from_rest = Envelope::new(c, Rise::RunWide, F, A, J);
            for k in 1..200 {
                let t = k as f64 * 1e-3;
                let (v, x) = (c + 0.5 * J * t * t, c * t + J * t * t * t / 6.0);
                if v > 0.5 * F || J * t > A {
                    break;
                }
                for e in [&env, &from_rest] {
                    assert!(e.at(x) >= v * (1.0 - 1e-12), "c {c}, t {t}");
                    assert!(e.time_to(x) <= t * (1.0 + 1e-12), "c {c}, t {t}");
                }
            }
        }
    }
}
