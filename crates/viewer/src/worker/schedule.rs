//! The worker thread's loop and what it renders when: the levels of a job, planned from
//! the frame times it learnt, and the growing batches of a path-traced job.

use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use super::draw::path_traced;
use super::{
    lock, Frame, Job, Level, Shared, Worker, ABANDON_FIRST_MS, FRAME_BUDGET_MS, PATH_BATCH_MS,
    PATH_CAP, SETTLE_MS,
};

impl Worker {
    pub(super) fn run(&mut self, sh: &Shared, repaint: &(dyn Fn() + Send + Sync)) {
        loop {
            let (n, job) = {
                let mut slot = lock(&sh.job);
                loop {
                    if sh.quit.load(Ordering::SeqCst) {
                        return;
                    }
                    if let Some(j) = slot.take() {
                        break j;
                    }
                    slot = sh
                        .wake
                        .wait(slot)
                        .unwrap_or_else(std::sync::PoisonError::into_inner);
                }
            };
            sh.busy.store(true, Ordering::SeqCst);
            let stale = || sh.newest.load(Ordering::SeqCst) != n;
            let mut levels = self.plan(&job);
            // A path-traced job's levels grow as they are rendered (`next_paths`).
            for i in 0.. {
                let Some(&level) = levels.get(i) else { break };
                let from = paths_before(&levels, i);
                if i == 1 && job.interactive && Self::newer_within(sh, n, SETTLE_MS) {
                    break;
                }
                // A job's first level is what the user waits for: a newer job abandons it
                // only once it runs well past the budget (else a drag whose events come
                // faster than frames would abandon every frame and show none); later
                // levels are refinements, abandoned at once.
                let started = Instant::now();
                let long = || started.elapsed().as_secs_f64() * 1e3 > ABANDON_FIRST_MS;
                let first_stop = || stale() && long();
                let stop: &(dyn Fn() -> bool + Sync) = if i == 0 { &first_stop } else { &stale };
                // A panic in a frame (a renderer bug) must not kill the worker: the frame is
                // dropped and the next job starts from fresh renderers.
                let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    self.render_level(&job, n, (level, from), stop)
                }));
                match result {
                    Ok(Ok(frame)) => {
                        if i + 1 == levels.len() {
                            let ms = started.elapsed().as_secs_f64() * 1e3;
                            levels.extend(next_paths(level, from, path_cap(&job), ms));
                        }
                        let last = i + 1 == levels.len();
                        *lock(&sh.frame) = Some(Frame { last, ..frame });
                        repaint();
                    }
                    Ok(Err(_)) => {
                        if i == 0 {
                            // Too slow to finish: the next job plans a smaller first frame.
                            let spent = started.elapsed().as_secs_f64() * 1e3;
                            let slot = &mut self.times_of(level)[level.divisor() as usize];
                            *slot = Some(slot.map_or(spent, |e| e.max(spent)));
                        }
                        break;
                    }
                    Err(_) => {
                        *self = Worker::default();
                        break;
                    }
                }
            }
            sh.busy.store(false, Ordering::SeqCst);
            repaint();
        }
    }

    /// Waits up to `ms` for a job newer than `n`; true if one arrived.
    fn newer_within(sh: &Shared, n: u64, ms: u64) -> bool {
        let deadline = Instant::now() + Duration::from_millis(ms);
        let mut slot = lock(&sh.job);
        loop {
            if sh.newest.load(Ordering::SeqCst) != n || sh.quit.load(Ordering::SeqCst) {
                return true;
            }
            let now = Instant::now();
            if now >= deadline {
                return false;
            }
            slot = sh
                .wake
                .wait_timeout(slot, deadline - now)
                .map(|(g, _)| g)
                .unwrap_or_else(|e| e.into_inner().0);
        }
    }

    /// The frame times of a level's scene: the simplified copy's, or the scene's.
    pub(super) fn times_of(&mut self, level: Level) -> &mut [Option<f64>; 5] {
        match level {
            Level::Simplified(_) => &mut self.proxy_times,
            Level::Reduced(_) | Level::Full | Level::Supersampled(_) | Level::Paths(_) => {
                &mut self.times
            }
        }
    }

    /// The levels to render for a job, coarsest first.
    fn plan(&self, job: &Job) -> Vec<Level> {
        let mut levels = Vec::new();
        if job.interactive {
            if job.proxy.is_some() {
                levels.push(Level::Simplified(divisor(&self.proxy_times)));
            } else {
                let d = divisor(&self.times);
                if d > 1 {
                    levels.push(Level::Reduced(d));
                }
            }
        }
        if accumulates(job) {
            levels.push(Level::Paths(1));
            return levels;
        }
        levels.push(Level::Full);
        for n in [2, 4] {
            if job.max_samples >= n {
                levels.push(Level::Supersampled(n));
            }
        }
        levels
    }
}

/// Records a frame time `ms` at divisor `d` (a moving average) and corrects the other
/// divisors' times that it contradicts: a frame at 1/k resolution has (d/k)² times the
/// pixels of one at 1/d, so it cannot honestly cost more than that ratio (at least 1) times
/// as much; a time more than twice over is stale (one frame slowed by a busy machine or a
/// first-use cost) and is set to the ratio. Without this, one slow full-resolution frame
/// kept every later interactive frame reduced, since reduced frames never measure the full
/// one again (an animation of 0.4 ms frames played at 1/2 resolution for good).
pub(super) fn record(times: &mut [Option<f64>; 5], d: usize, ms: f64) {
    let Some(slot) = times.get_mut(d) else { return };
    let t = slot.map_or(ms, |old| 0.5 * (old + ms));
    *slot = Some(t);
    for (k, slot) in times.iter_mut().enumerate().skip(1) {
        let ceiling = t * ((d * d) as f64 / (k * k) as f64).max(1.0);
        if let Some(tk) = slot {
            if k != d && *tk > 2.0 * ceiling {
                *tk = ceiling;
            }
        }
    }
}

/// The resolution divisor (1..=4) for a frame that should fit [`FRAME_BUDGET_MS`], from the
/// frame times `times`: the smallest whose time (measured, or extrapolated from the nearest
/// measured divisor as if cost followed the pixel count) fits; if none does, the fastest,
/// preferring the larger image within 10% (a frame bound by geometry gains nothing from
/// fewer pixels).
fn divisor(times: &[Option<f64>; 5]) -> u32 {
    {
        let estimate = |d: usize| -> Option<f64> {
            times[d].or_else(|| {
                (1..=4)
                    .filter_map(|k| times[k].map(|t| (k, t)))
                    .min_by_key(|(k, _)| k.abs_diff(d))
                    .map(|(k, t)| t * (k * k) as f64 / (d * d) as f64)
            })
        };
        let Some(full) = estimate(1) else {
            return 1;
        };
        if full <= FRAME_BUDGET_MS {
            return 1;
        }
        let est: Vec<(u32, f64)> = (2..=4u32)
            .map(|d| (d, estimate(d as usize).unwrap_or(f64::INFINITY)))
            .collect();
        if let Some(&(d, _)) = est.iter().find(|(_, t)| *t <= FRAME_BUDGET_MS) {
            return d;
        }
        let fastest = est.iter().map(|e| e.1).fold(f64::INFINITY, f64::min);
        est.iter()
            .find(|(_, t)| *t <= fastest * 1.1)
            .map_or(4, |&(d, _)| d)
    }
}

/// Whether a job accumulates paths: its A side is path traced (a path-traced B beside
/// another A follows A's levels: supersampled, its passes one path each).
pub(super) fn accumulates(job: &Job) -> bool {
    path_traced(&job.a)
}

/// Paths per pixel a path-traced job accumulates: [`PATH_CAP`], or one when refinement is
/// off (`max_samples` 1).
pub(super) fn path_cap(job: &Job) -> u32 {
    if job.max_samples > 1 {
        PATH_CAP
    } else {
        1
    }
}

/// Paths per pixel summed by the levels before `levels[i]` (0 unless it follows a
/// [`Level::Paths`]).
fn paths_before(levels: &[Level], i: usize) -> u32 {
    match i.checked_sub(1).map(|j| levels[j]) {
        Some(Level::Paths(n)) => n,
        _ => 0,
    }
}

/// The level after `level` of a path-traced job, which added paths `from..n` in `ms`
/// milliseconds: the batch doubles (as many paths again as summed so far) unless that
/// would take longer than [`PATH_BATCH_MS`] (then as many as fit, at least one), up to
/// `cap` paths per pixel; `None` at the cap or after any other level.
fn next_paths(level: Level, from: u32, cap: u32, ms: f64) -> Option<Level> {
    let Level::Paths(n) = level else { return None };
    if n >= cap {
        return None;
    }
    let per_path = ms / f64::from(n.saturating_sub(from).max(1));
    // A float beyond u32's range saturates.
    let fits = (PATH_BATCH_MS / per_path.max(1e-9)).floor() as u32;
    let batch = n.min(fits).max(1).min(cap - n);
    Some(Level::Paths(n + batch))
}

#[cfg(test)]
mod tests {
    use super::{divisor, next_paths, record, Level, FRAME_BUDGET_MS, PATH_BATCH_MS, PATH_CAP};

    #[test]
    fn path_batches_double_within_the_batch_time_up_to_the_cap() {
        let quick = |level, from| next_paths(level, from, PATH_CAP, 1.0);
        let mut n = Level::Paths(1);
        let mut from = 0;
        let mut counts = vec![1];
        while let Some(next) = quick(n, from) {
            let Level::Paths(k) = next else { panic!() };
            (from, n) = (counts[counts.len() - 1], next);
            counts.push(k);
        }
        assert_eq!(counts, [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]);
        // A slow batch (8 paths in 4 batch times): the next adds 2 paths, not 16.
        let slow = next_paths(Level::Paths(16), 8, PATH_CAP, 4.0 * PATH_BATCH_MS);
        assert_eq!(slow, Some(Level::Paths(18)));
        // Slower than a batch time per path: one at a time.
        let slower = next_paths(Level::Paths(16), 8, PATH_CAP, 80.0 * PATH_BATCH_MS);
        assert_eq!(slower, Some(Level::Paths(17)));
        // The cap is not passed, and nothing follows other levels.
        assert_eq!(
            next_paths(Level::Paths(1000), 500, PATH_CAP, 1.0),
            Some(Level::Paths(1024))
        );
        assert_eq!(next_paths(Level::Paths(1), 0, 1, 1.0), None);
        assert_eq!(next_paths(Level::Full, 0, PATH_CAP, 1.0), None);
    }

    #[test]
    fn one_slow_full_frame_does_not_keep_later_frames_reduced() {
        let mut times = [None; 5];
        // A first full frame slowed far past the budget: the next is reduced.
        record(&mut times, 1, FRAME_BUDGET_MS * 5.0);
        assert!(divisor(&times) > 1);
        // The reduced frame is fast: full resolution cannot cost more than 4x that.
        let d = divisor(&times) as usize;
        record(&mut times, d, 0.1);
        assert_eq!(divisor(&times), 1, "{times:?}");
        assert!(times[1].unwrap() <= 0.1 * (d * d) as f64);
        // Times consistent with the pixel counts (fill bound: 4x; geometry bound: 1x) stay.
        let mut fill = [None, Some(40.0), None, None, None];
        record(&mut fill, 2, 10.0);
        assert_eq!(fill[1], Some(40.0));
        let mut geometry = [None, Some(40.0), None, None, None];
        record(&mut geometry, 2, 39.0);
        assert_eq!(geometry[1], Some(40.0));
        // A smaller image slower than twice a larger one is stale too.
        let mut small = [None, None, Some(500.0), None, None];
        record(&mut small, 1, 10.0);
        assert_eq!(small[2], Some(10.0));
    }
}
