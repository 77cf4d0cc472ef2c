//! The second half of writing a part ([`super::choose`] the first): the
//! chosen renderings written from where the text before the part leaves
//! the writer, read back from where its reading stands, verified against
//! the original and timed; a run that fails is rendered again with half
//! the chord share, a few times, then kept as the program wrote it, and a
//! run that reads back slower than the program's own is kept as written.

use super::choose::Chosen;
use super::emitter::{Choice, Emitter};
use super::{EmitError, Emitted, PartContext, Result, PARALLEL_FEEDS_PIECES, RETRIES};
use crate::pipeline::{compare_runs, pair_runs, WrittenReading};
use crate::RunOutput;
use fairpath::feed::plan::Corners;
use fairpath::path::Run;
use fairpath::pipeline::par_map;
use fairpath::render::RenderStats;

/// Writes `chosen`, the renderings of `em`'s runs, from where `ctx`
/// stands, and leaves it standing after the text (see the module docs).
pub(super) fn write_chosen(
    em: &Emitter,
    ctx: &mut PartContext,
    original: &[Run],
    chosen: Chosen,
) -> Result<Emitted> {
    let (program, feeds, opts, wo) = (em.program, &em.feeds, &em.opts, &em.wo);
    let tolerance = opts.budget.written();
    let nf = feeds.len();
    let time = |pieces: &[fairpath::path::Piece], f: bool| em.time(pieces, f);
    let render = |k: usize, form, chord: f64| em.render(k, form, chord);
    let at_feeds = |len: usize, t: &(dyn Fn(bool) -> Result<f64> + Sync)| em.at_feeds(len, t);
    let Chosen {
        mut choices,
        own,
        g91_spline_runs,
    } = chosen;
    let mut retried = vec![false; choices.len()];
    // Write, read back, verify and time per run until every rewritten run
    // verifies and is faster than the program's own. A run that fails is
    // rendered again with half the chord, up to RETRIES times, then kept
    // as written; one that reads back slower is kept as written at once.
    // Runs kept as written always verify and are never slower, so the text
    // returned is the one written last.
    let mut attempt = 0;
    loop {
        let outputs: Vec<RunOutput> = choices
            .iter()
            .map(|c| match c.form {
                Some(_) => RunOutput::Rendered(&c.pieces, &c.speeds),
                None => RunOutput::Original,
            })
            .collect();
        let mut carry = ctx.carry.clone();
        let text = crate::write_gcode::write_part(program, &outputs, wo, &ctx.facts, &mut carry)
            .map_err(EmitError::WriteGcode)?;
        // The rendered pieces are in the text now, and on a long run they
        // are among the largest things held: dropped before the text is
        // read back (rendering is deterministic: a retry renders them again).
        drop(outputs);
        for c in &mut choices {
            c.pieces = Vec::new();
            c.speeds = Vec::new();
        }
        // Read back for what checking and planning it need (its motions
        // and runs' pieces; no lines held: on long outputs the reading is
        // the largest thing held).
        let (reading_after, reread_outline, reread) = ctx
            .reading
            .read_part(text.as_bytes())
            .map_err(EmitError::Reread)?;
        let check = compare_runs(original, &reread, tolerance)?;
        #[allow(unused_mut)]
        let mut failed: Vec<usize> = check.failed_runs.iter().flatten().copied().collect();
        #[cfg(test)]
        if attempt == 0 {
            failed.extend(super::tests::FAIL_FIRST_CHECK.with(|f| f.take()));
        }
        let mut is_failed = vec![false; choices.len()];
        for &k in &failed {
            is_failed[k] = true;
        }
        let pairs = pair_runs(original, &reread)?;
        // The feed `fairpath simulate` plans the written program at, and
        // whether `time` plans as it does there (then its time is kept for
        // the written program's plan).
        let user_feed = feeds.iter().position(|&f| f == opts.override_feed);
        let as_simulate = opts.judged_by == Corners::Blended;
        // (the run is slower than the program's own, its time at the
        // user's feed).
        type Judged = (Option<usize>, Option<f64>);
        let judged: Vec<Judged> = par_map(pairs.len(), |i| -> Result<Judged> {
            let (o, c) = pairs[i];
            if choices[o].form.is_none() || is_failed[o] {
                return Ok((None, None));
            }
            let pieces = &reread[c].pieces;
            let kept = |ts: &[f64]| {
                user_feed
                    .filter(|_| as_simulate)
                    .and_then(|u| ts.get(u).copied())
            };
            if pieces.len() >= PARALLEL_FEEDS_PIECES {
                let ts = at_feeds(pieces.len(), &|f| time(pieces, f))?;
                let slower = ts.iter().zip(&own[o]).any(|(t, w)| t > w);
                return Ok((slower.then_some(o), kept(&ts)));
            }
            let mut ts = Vec::with_capacity(nf);
            for (fi, &f) in feeds.iter().enumerate() {
                ts.push(time(pieces, f)?);
                if ts[fi] > own[o][fi] {
                    return Ok((Some(o), None));
                }
            }
            Ok((None, kept(&ts)))
        })
        .into_iter()
        .collect::<Result<Vec<_>>>()?;
        let slower: Vec<usize> = judged.iter().filter_map(|j| j.0).collect();
        // Nothing left to change, or nothing this loop can change (a run
        // the program wrote itself fails: the caller refuses).
        let stuck = failed.iter().any(|&k| choices[k].form.is_none());
        if (failed.is_empty() && slower.is_empty()) || stuck {
            let mut stats = RenderStats::default();
            for c in &choices {
                stats.add(&c.stats);
            }
            let kept: Vec<bool> = choices.iter().map(|c| c.form.is_none()).collect();
            let kept_runs = kept.iter().filter(|&&k| k).count();
            let mut run_times = vec![None; reread.len()];
            for (&(_, c), j) in pairs.iter().zip(&judged) {
                run_times[c] = j.1;
            }
            ctx.carry = carry;
            ctx.reading = reading_after;
            return Ok(Emitted {
                budget: opts.budget,
                text,
                stats,
                check,
                retried_runs: retried.iter().filter(|&&r| r).count(),
                g91_spline_runs,
                kept_runs,
                kept,
                reading: Some(WrittenReading {
                    outline: reread_outline,
                    runs: reread,
                    run_times,
                }),
            });
        }
        attempt += 1;
        for o in slower {
            choices[o] = Choice::original(choices[o].chord);
        }
        for k in failed {
            retried[k] = true;
            let (form, chord) = (choices[k].form, choices[k].chord);
            choices[k] = match form {
                Some(form) if attempt < RETRIES => render(k, form, 0.5 * chord)?,
                _ => Choice::original(chord),
            };
        }
        // Every other rewritten run is rendered again for the next text.
        for (k, c) in choices.iter_mut().enumerate() {
            if let (Some(form), true) = (c.form, c.pieces.is_empty()) {
                *c = render(k, form, c.chord)?;
            }
        }
    }
}
