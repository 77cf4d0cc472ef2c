//! The second half of writing a part ([`super::choose`] the first): the
//! chosen renderings written from where the text before the part leaves
//! the writer, read back from where its reading stands, verified against
//! the original and timed; a run that fails is rendered again with half
//! the chord share, a few times, then kept as the program wrote it, and a
//! run that reads back slower than the program's own is kept as written.
//!
//! A long run whose only candidate is timed as written
//! ([`Choice::streamed`]) is rendered as the writer writes it, part after
//! part ([`PartsRenderer`]), and checked and timed as its text is read
//! back, part after part ([`super::streamed`]): neither its rendering nor
//! its reading is held whole (both are large on a one-run raster written
//! as arcs; measurements: docs/tuning.md, `emit::write`). The text and the
//! evidence are those of the run rendered and read whole
//! (`a_long_run_written_as_it_is_rendered_is_the_run_rendered_whole`).

use super::choose::{choose_run, Chosen};
use super::emitter::{Choice, Emitter, PartsRenderer};
use super::streamed;
use super::{EmitError, Emitted, PartContext, Result, PARALLEL_FEEDS_PIECES, RETRIES};
use crate::pipeline::{compare_runs_known, WrittenReading};
use crate::text_out::TextOut;
use crate::write_gcode::WriterCarry;
use crate::RunOutput;
use fairpath::feed::plan::Corners;
use fairpath::path::Run;
use fairpath::pipeline::par_map;
use fairpath::render::{CurveForm, RenderStats};
use fairpath::verify::RunReport;
use std::cell::RefCell;
use std::io::Read;

/// Writes `chosen`, the renderings of `em`'s runs, from where `ctx`
/// stands, and leaves it standing after the text (see the module docs).
pub(super) fn write_chosen(
    em: &Emitter,
    ctx: &mut PartContext,
    original: &[Run],
    chosen: Chosen,
    out: &mut dyn TextOut,
) -> Result<Emitted> {
    let (feeds, opts) = (&em.feeds, &em.opts);
    let tolerance = opts.budget.written();
    let nf = feeds.len();
    let time = |pieces: &[fairpath::path::Piece], f: bool| em.time(pieces, f);
    let render = |k: usize, form, chord: f64, share| em.render(k, form, chord, share);
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
    // left in `out` is the one written last: the part's text goes there as
    // it is written, from `start` on, and a text written again replaces it.
    let start = out.written().map_err(EmitError::Output)?;
    let mut attempt = 0;
    loop {
        out.cut(start).map_err(EmitError::Output)?;
        let (lines, carry, rendered) = write_text(em, ctx, &choices, out)?;
        for (k, r) in rendered {
            if let Some(e) = r.error {
                return Err(e);
            }
            (choices[k].stats, choices[k].count) = (r.stats, r.count);
        }
        // A long run's arcs that fell back to G1 on many blocks have the
        // all-G1 candidate to beat (`choose`): chosen again among every
        // form, rendered whole, and the text written again.
        let mut rechosen = false;
        for k in 0..choices.len() {
            let c = &choices[k];
            let arcs = c.form == Some(CurveForm::Arcs) && em.forms.len() > 1;
            if c.streamed && arcs && !em.long_with_few_lines(k, c) {
                choices[k] = choose_run(em, k, original, &own[k], false)?;
                rechosen = true;
            }
        }
        if rechosen {
            continue;
        }
        // The rendered pieces are in the text now, and on a long run they
        // are among the largest things held: dropped before the text is
        // read back (rendering is deterministic: a retry renders them again).
        for c in &mut choices {
            c.pieces = Vec::new();
            c.speeds = Vec::new();
        }
        // Read back for what checking and planning it need (its motions
        // and runs' pieces; no lines held: on long outputs the reading is
        // the largest thing held); the runs rendered as they were written
        // checked and timed as they are read, not held.
        // (Without the cut line the part before held back, where it is
        // written here; with the one this part holds back.)
        let rewritten_first = choices.first().is_some_and(|c| c.form.is_some());
        let prefix = ctx
            .carry
            .cut_line()
            .filter(|_| em.program.window_continued() && rewritten_first)
            .map_or(0, str::len);
        let cut = (start + prefix as u64, carry.cut_line().unwrap_or(""));
        let (reading_after, reread_outline, reread, streamed) =
            read_back(em, ctx, original, &choices, out, cut, tolerance)?;
        let known: Vec<(usize, RunReport)> = streamed
            .iter()
            .map(|r| (r.candidate, r.report.clone()))
            .collect();
        let (check, pairs) = compare_runs_known(original, &reread, tolerance, &known)?;
        let streamed_of = |c: usize| streamed.iter().find(|r| r.candidate == c);
        #[allow(unused_mut)]
        let mut failed: Vec<usize> = check.failed_runs.iter().flatten().copied().collect();
        // (for the first part with a run)
        #[cfg(test)]
        if attempt == 0 && !choices.is_empty() {
            failed.extend(super::tests::FAIL_FIRST_CHECK.with(|f| f.take()));
        }
        let mut is_failed = vec![false; choices.len()];
        for &k in &failed {
            is_failed[k] = true;
        }
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
            let kept = |ts: &[f64]| {
                user_feed
                    .filter(|_| as_simulate)
                    .and_then(|u| ts.get(u).copied())
            };
            // A run checked as it was read holds no pieces: its times are
            // those planned then (every one known: `read_back`), its time
            // at the user's feed kept whatever the verdict.
            if let Some(r) = streamed_of(c) {
                let ts: Vec<f64> = r.times[..nf].iter().flatten().copied().collect();
                let user = if as_simulate { kept(&ts) } else { r.times[nf] };
                let judged = choices[o].form.is_some() && !is_failed[o];
                let slower = judged && ts.iter().zip(&own[o]).any(|(t, w)| t > w);
                return Ok((slower.then_some(o), user));
            }
            if choices[o].form.is_none() || is_failed[o] {
                return Ok((None, None));
            }
            let pieces = &reread[c].pieces;
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
                lines,
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
            let c = &choices[k];
            choices[k] = match c.form {
                Some(form) if attempt < RETRIES && c.streamed => Choice {
                    part_pieces: c.part_pieces,
                    ..Choice::streamed(form, 0.5 * c.chord)
                },
                Some(form) if attempt < RETRIES => render(k, form, 0.5 * c.chord, c.step_share)?,
                _ => Choice::original(c.chord),
            };
        }
        // Every other rewritten run is rendered again for the next text
        // (those rendered as they are written, as they are written again).
        for (k, c) in choices.iter_mut().enumerate() {
            if let (Some(form), true, false) = (c.form, c.pieces.is_empty(), c.streamed) {
                *c = render(k, form, c.chord, c.step_share)?;
            }
        }
    }
}

/// Reads the part written with `choices` back from `out`, where it starts
/// at byte `start`, followed by `held` (the cut line the part holds back:
/// [`WriterCarry::cut_line`]), from where `ctx` stands. The runs rendered as they
/// were written ([`Choice::streamed`]) are checked and timed as they are
/// read ([`streamed::read_checking`]);
/// where one of them could not be timed that way (windows that do not
/// stitch) or the runs do not pair as they were taken to, the text is read
/// again whole (and checked as any other).
fn read_back(
    em: &Emitter,
    ctx: &PartContext,
    original: &[Run],
    choices: &[Choice],
    out: &mut dyn TextOut,
    (start, held): (u64, &str),
    tolerance: f64,
) -> Result<streamed::Checked> {
    if streamed::takes_any(choices) {
        let reading = &ctx.reading;
        let text = out.read_from(start).map_err(EmitError::Output)?;
        let mut text = text.chain(held.as_bytes());
        let (after, outline, runs, done) =
            streamed::read_checking(em, reading, &mut text, original, choices, tolerance)?;
        let timed = done.iter().all(|r| r.times.iter().all(Option::is_some));
        #[cfg(test)]
        let timed = timed && !super::tests::UNSTITCHED.with(|n| n.get());
        let streamed: Vec<usize> = done.iter().map(|r| r.candidate).collect();
        let paired =
            crate::pipeline::pair_runs_streamed(original, &runs, &streamed).is_ok_and(|pairs| {
                done.iter()
                    .all(|r| pairs.contains(&(r.original, r.candidate)))
            });
        if timed && paired {
            #[cfg(test)]
            super::tests::STREAMED_RUNS.with(|n| n.set(n.get() + done.len()));
            return Ok((after, outline, runs, done));
        }
        #[cfg(test)]
        super::tests::READ_AGAIN.with(|n| n.set(n.get() + 1));
    }
    let text = out.read_from(start).map_err(EmitError::Output)?;
    let mut text = text.chain(held.as_bytes());
    let (after, outline, runs) = ctx.reading.read_part_from(&mut text)?;
    Ok((after, outline, runs, Vec::new()))
}

/// The lines of a part's text, the writer's state after it, and the
/// renderers of its runs rendered as they were written, by run
/// ([`write_text`]).
type Written<'e> = (usize, WriterCarry, Vec<(usize, PartsRenderer<'e>)>);

/// The text of the part with `choices`, from where `ctx` stands, written
/// to the end of `out`: its lines and the writer's state after it; with
/// the renderers of the runs rendered as they are written
/// ([`Choice::streamed`]), by run, which hold what they rendered (stats,
/// count) or the error that stopped them.
///
/// (Rendering each such run on a thread of its own a group ahead of the
/// writer was tried: the same wall time on two cores, which the rendering
/// keeps busy.)
fn write_text<'e>(
    em: &Emitter<'e>,
    ctx: &PartContext,
    choices: &[Choice],
    out: &mut dyn TextOut,
) -> Result<Written<'e>> {
    let mut carry = ctx.carry.clone();
    let mut renderers: Vec<Option<RefCell<PartsRenderer>>> = Vec::with_capacity(choices.len());
    for (k, c) in choices.iter().enumerate() {
        let Some(form) = c.form.filter(|_| c.streamed) else {
            renderers.push(None);
            continue;
        };
        let (ro, speed) = em.render_setup(k, form, c.chord, c.step_share)?;
        let group = super::streamed_group_parts();
        let parts = PartsRenderer::new(k, &em.smoothed[k], ro, speed, (group, c.part_pieces));
        renderers.push(Some(RefCell::new(parts)));
    }
    let outputs: Vec<RunOutput> = choices
        .iter()
        .zip(&renderers)
        .map(|(c, r)| match (c.form, r) {
            (Some(_), Some(r)) => RunOutput::Parts(r),
            (Some(_), None) => RunOutput::Rendered(&c.pieces, &c.speeds),
            (None, _) => RunOutput::Original,
        })
        .collect();
    let lines =
        crate::write_gcode::write_part(em.program, &outputs, &em.wo, &ctx.facts, &mut carry, out)
            .map_err(EmitError::WriteGcode)?;
    drop(outputs);
    let rendered = renderers
        .into_iter()
        .enumerate()
        .filter_map(|(k, r)| Some((k, r?.into_inner())))
        .collect();
    Ok((lines, carry, rendered))
}
