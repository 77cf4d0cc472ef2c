//! The first half of writing a part: for each run, the rendering that
//! plans fastest among the forms the format allows, or the run as the
//! program wrote it when none is faster than it at every feed. It needs
//! nothing of the parts before, so it can run while they are written
//! ([`super::write`]).

use super::emitter::{Choice, Emitter};
use super::{
    Result, FINER_KEEP_MARGIN, LONG_RUN_PIECES, PARALLEL_FEEDS_PIECES, RENDER_PART_PIECES,
    STREAMED_PART_RENDERED,
};
use fairpath::path::Run;
use fairpath::pipeline::par_map;
use fairpath::render::CurveForm;

/// The renderings chosen for a part's runs ([`super::choose_part`]), and the planned
/// times of the program's own runs that they were judged against.
pub struct Chosen {
    pub(super) choices: Vec<Choice>,
    /// Each run's own time at each of [`Emitter::feeds`] (infinite for a
    /// run smoothed into itself, which is written as it is).
    pub(super) own: Vec<Vec<f64>>,
    /// Runs kept as written because they are in G91 and the format has
    /// only spline blocks, which would need G90 around them.
    pub(super) g91_spline_runs: usize,
}

/// The renderings of `em`'s runs (`original` the program's own).
pub(super) fn choose(em: &Emitter, original: &[Run]) -> Result<Chosen> {
    let (smoothed, feeds, forms, opts) = (em.smoothed, &em.feeds, &em.forms[..], &em.opts);
    let time = |pieces: &[fairpath::path::Piece], f: bool| em.time(pieces, f);
    // A run smoothed into itself (method `none`) is written as the program
    // wrote it: no rendering could say it more exactly, and its own times
    // are not needed.
    let itself: Vec<bool> = par_map(smoothed.len(), |k| smoothed[k] == original[k].pieces);
    let nf = feeds.len();
    // The planned time of each of the program's own runs, at each feed:
    // side by side by run, and a long run's feeds side by side too (each
    // planned window by window, `Emitter::time`: two plans at once hold
    // two windows).
    let own: Vec<Vec<f64>> = par_map(smoothed.len(), |k| {
        if itself[k] {
            return Ok(vec![f64::INFINITY; nf]);
        }
        let pieces = &original[k].pieces;
        em.at_feeds(pieces.len(), &|f| time(pieces, f))
    })
    .into_iter()
    .collect::<Result<_>>()?;
    let chosen: Vec<Result<Choice>> = par_map(smoothed.len(), |k| {
        if itself[k] {
            return Ok(Choice::original(opts.budget.output));
        }
        choose_run(em, k, original, &own[k], true)
    });
    let choices: Vec<Choice> = chosen.into_iter().collect::<Result<_>>()?;
    let splines_only = forms.iter().all(|f| matches!(f, CurveForm::Nurbs(_)));
    let g91_spline_runs = (0..smoothed.len())
        .filter(|&k| splines_only && !itself[k] && em.program.run_spans()[k].incremental)
        .count();
    Ok(Chosen {
        choices,
        own,
        g91_spline_runs,
    })
}

/// The rendering of run `k` that plans fastest among the forms the
/// format allows, or the run as the program wrote it (`own`: its time at
/// each of [`Emitter::feeds`]) where none is faster at every feed. With
/// `stream`, a long run's first candidate that would be timed only as
/// written is chosen unrendered, to be rendered as it is written
/// ([`Choice::streamed`]); [`super::write`] chooses again without
/// `stream` where its arcs fell back to G1 on too many blocks for that.
pub(super) fn choose_run(
    em: &Emitter,
    k: usize,
    original: &[Run],
    own: &[f64],
    stream: bool,
) -> Result<Choice> {
    let (smoothed, feeds, forms, opts) = (em.smoothed, &em.feeds, &em.forms[..], &em.opts);
    let rendered_time = |c: &Choice, f: bool| em.rendered_time(c, f);
    let at_feeds = |len: usize, t: &(dyn Fn(bool) -> Result<f64> + Sync)| em.at_feeds(len, t);
    // The fastest rendering so far, with its time at each feed.
    let mut best: Option<(Vec<f64>, Choice)> = None;
    // The margin a rendering must gain on the run as written (none on a
    // run of splines, `KEEP_MARGIN` on others), as `auto`'s objective
    // judges it (`Objective::written_instead`).
    let margin = fairpath::choose::rewrite_margin(&original[k].pieces);
    // Whether the arcs rendering holds no arc.
    let mut arcs_all_lines = false;
    // A long run whose arcs fell back to G1 on few blocks.
    let long_with_few_lines = |c: &Choice| em.long_with_few_lines(k, c);
    for (i, &form) in forms.iter().enumerate() {
        // A spline block in a G91 run is written between a G90 and a
        // G91 line, which end a run where the program had none (the
        // written program would not pair with the original): such a
        // run gets the format's other forms, or stays as written.
        if matches!(form, CurveForm::Nurbs(_)) && em.program.run_spans()[k].incremental {
            continue;
        }
        // G1 is the other candidate for curves that arcs could not
        // follow: where they all became arcs one curve at a time, it is
        // not tried; nor on a long run where few did. Chains of arcs
        // (`fairpath::render::RenderStats::chained`) smooth over the
        // curves' bumps, which G1 may follow faster (measurements:
        // docs/tuning.md, `render::chain_arcs`): there it is tried.
        if i > 0
            && form == CurveForm::Lines
            && best.as_ref().is_some_and(|(_, b)| {
                (b.stats.fallback_lines == 0 && b.stats.chained == 0) || long_with_few_lines(b)
            })
        {
            continue;
        }
        // Where a NURBS rendering won, the curves are written as the
        // spline they are: arcs and lines are the other candidates
        // where it loses (their written coordinates round by parts in
        // ten thousand, which a NURBS's control points barely do).
        if best
            .as_ref()
            .is_some_and(|(_, b)| matches!(b.form, Some(CurveForm::Nurbs(_))))
        {
            continue;
        }
        // (The time at the user's feeds where `auto`'s objective made
        // this rendering.)
        // The all-G1 alternative, where the arcs rendering holds no arc,
        // at the finer chord of G1 output (at the arcs' chord it would
        // be the same rendering: `Emitter::finer_lines_chord`).
        let chord = match em.finer_lines_chord() {
            Some(finer) if form == CurveForm::Lines && i > 0 && arcs_all_lines => finer,
            _ => opts.budget.output,
        };
        // A long run's first candidate that is timed only as written is
        // rendered as it is written ([`Emitter::streams`]).
        if stream && best.is_none() && i == 0 && em.streams(k, form, chord) {
            return Ok(Choice::streamed(form, chord));
        }
        // A candidate must be faster than the program's own run at every
        // feed, and than a rendering already chosen at the first: it
        // loses at the first feed where it is not, and its times at the
        // feeds after that are not planned. A long run is planned at
        // every feed side by side (once it beats the chosen one at the
        // first).
        let loses = |fi: usize, t: f64| {
            t * (1.0 + margin) > own[fi] || (fi == 0 && best.as_ref().is_some_and(|b| t >= b.0[0]))
        };
        // The all-G1 alternative to a rendering of many pieces (a long
        // run's, or one whose every curve renders to hundreds of blocks:
        // a pen plotter's fits, 649 curves to 666,122 lines) is timed as
        // it is rendered, part after part, and where it wins it is
        // rendered again as it is written: never held whole.
        let many = best
            .as_ref()
            .map(|(_, b)| b.count)
            .filter(|&n| n >= LONG_RUN_PIECES);
        let streams = i > 0 && em.may_stream() && !em.goes_on(k);
        if let (Some(count), CurveForm::Lines, true) = (many, form, streams) {
            let part = streamed_part_pieces(smoothed[k].len(), count);
            if let Some(ts) = em.streamed_times(k, (form, chord), part)? {
                if ts.iter().enumerate().all(|(fi, &t)| !loses(fi, t)) {
                    let c = Choice {
                        part_pieces: part,
                        ..Choice::streamed(form, chord)
                    };
                    best = Some((ts, c));
                }
                continue;
            }
        }
        let (c, known) = em.first_render(k, i, chord)?;
        if form == CurveForm::Arcs {
            arcs_all_lines = c.stats.arcs == 0;
        }
        let rendered_time = |c: &Choice, f: bool| match known {
            Some(t) if f == opts.override_feed => Ok(t),
            _ => rendered_time(c, f),
        };
        // A long run's only candidate is timed once, as written (the
        // check below plans what reads back at every feed and keeps the
        // run as the program wrote it where that is slower).
        let sole = i + 1 == forms.len() || (form == CurveForm::Arcs && long_with_few_lines(&c));
        if best.is_none() && sole && em.is_long(k) {
            return Ok(c);
        }
        let ts = if c.pieces.len() >= PARALLEL_FEEDS_PIECES {
            if best.is_some() && loses(0, rendered_time(&c, feeds[0])?) {
                continue;
            }
            at_feeds(c.pieces.len(), &|f| rendered_time(&c, f))?
        } else {
            let mut ts = Vec::with_capacity(feeds.len());
            for &f in feeds.iter() {
                let t = rendered_time(&c, f)?;
                if loses(ts.len(), t) {
                    break;
                }
                ts.push(t);
            }
            ts
        };
        if ts.len() < feeds.len() || ts.iter().enumerate().any(|(fi, &t)| loses(fi, t)) {
            continue;
        }
        if best.as_ref().is_none_or(|(b, _)| ts[0] < b[0]) {
            best = Some((ts, c));
        }
    }
    // Arcs or G1 won: they are also tried at a finer curvature step
    // ([`super::FINER_STEP`]), where their joints pass faster than the
    // speed they were shaped for at the cost of more blocks, and kept where
    // that plans faster at every feed (not at the first alone, as the forms
    // are: the finer pieces must not slow the programmed feeds), by
    // [`FINER_KEEP_MARGIN`]: their written text reads back further from
    // their rendering; then finer again while each gains on the one before,
    // up to [`super::FINER_STEPS`] times. Not on a long run (it would be
    // rendered and planned twice more) nor on arcs that hold no arc.
    if let Some((t_first, c)) = &best {
        let form = match c.form {
            Some(CurveForm::Arcs) if c.stats.arcs > 0 => Some(CurveForm::Arcs),
            Some(CurveForm::Lines) => Some(CurveForm::Lines),
            _ => None,
        }
        .filter(|_| !c.streamed && !em.is_long(k));
        #[cfg(test)]
        let steps = super::tests::FINER_STEPS_TRIED.with(|n| n.get());
        #[cfg(not(test))]
        let steps = super::FINER_STEPS;
        let (chord, mut t_best, mut share) = (c.chord, t_first.clone(), opts.step_share);
        for _ in 0..steps {
            share *= super::FINER_STEP;
            let Some(form) = form.filter(|_| share > 0.0) else {
                break;
            };
            let finer = em.render(k, form, chord, Some(share))?;
            let mut ts = Vec::with_capacity(feeds.len());
            for &f in feeds.iter() {
                let t = rendered_time(&finer, f)?;
                let fi = ts.len();
                if t * (1.0 + margin) > own[fi] || t * (1.0 + FINER_KEEP_MARGIN) >= t_best[fi] {
                    break;
                }
                ts.push(t);
            }
            if ts.len() < feeds.len() {
                break;
            }
            t_best.clone_from(&ts);
            best = Some((ts, finer));
        }
    }
    Ok(best.map_or(Choice::original(opts.budget.output), |b| b.1))
}

/// Curves per part of a run of `curves` curves rendered part after part
/// where a rendering of it held `count` pieces: parts that render to
/// about [`STREAMED_PART_RENDERED`] pieces each, at most
/// [`RENDER_PART_PIECES`] curves; a multiple of the renderer's chains
/// ([`fairpath::render::CHAIN_PIECES`]) where it is longer than one, so
/// that the parts render as the whole.
fn streamed_part_pieces(curves: usize, count: usize) -> usize {
    let per_curve = count.div_ceil(curves.max(1)).max(1);
    let part = (STREAMED_PART_RENDERED / per_curve).clamp(1, RENDER_PART_PIECES);
    let chain = fairpath::render::CHAIN_PIECES;
    if part >= chain {
        part / chain * chain
    } else {
        part
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parts render to about [`STREAMED_PART_RENDERED`] pieces: a pen
    /// plotter's 649 fits whose arcs held 400,000 pieces go 48 curves a
    /// part; a curve that renders to more than that goes alone; a long
    /// run of corner transitions keeps the parts of the whole rendering.
    #[test]
    fn parts_of_a_rendering_timed_as_it_is_rendered() {
        assert_eq!(streamed_part_pieces(649, 400_000), 48);
        assert_eq!(streamed_part_pieces(3, 200_000), 1);
        assert_eq!(streamed_part_pieces(200_000, 400_000), RENDER_PART_PIECES);
        assert_eq!(streamed_part_pieces(10, 100), 2560);
    }
}
