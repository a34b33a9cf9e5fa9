//! A campaign: many seeds, on several threads, until a budget of simulated time is spent or a
//! run breaks a per-cycle invariant (or, keeping going, only the budget; a quiet phase that did not end in a usable HOLD is
//! collected, and the campaign goes on); what was reached, summed over the runs, and the
//! "sometimes" assertions (every mode and every kind of fault reached at least once).
//!
//! With one job the seeds run in order and a campaign is reproducible: the same options give
//! the same runs. With more, which seeds run before the budget is spent (or a run breaks an
//! invariant) depends on the threads' timing.

use crate::faults::Fault;
use crate::invariants::{LIMIT_OVERRUN_DEG, Violation};
use crate::run::{PlantedBug, RunOptions, RunReport, run};
use crate::shrink::invariant_of;
use mcm_shared::mode::Mode;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

/// How often a run over its CPU budget is run again to tell the machine's noise from the
/// controller's work (a real overrun comes back at the same cycle).
const MAX_RERUNS: usize = 2;

/// What to run.
#[derive(Debug, Clone, Copy)]
pub struct CampaignOptions {
    pub first_seed: u64,
    /// Simulated seconds in all (the last runs may go a little beyond).
    pub budget_s: f64,
    /// Simulated seconds of each run's chaos phase.
    pub run_s: f64,
    pub jobs: usize,
    pub planted: Option<PlantedBug>,
    /// Go on past a run that breaks a per-cycle invariant (collecting every failing run).
    pub keep_going: bool,
}

/// What a campaign did.
#[derive(Debug, Clone, Default)]
pub struct CampaignReport {
    pub runs: u64,
    pub simulated_s: f64,
    pub wall_s: f64,
    pub modes_reached: [u64; Mode::ALL.len()],
    pub faults_started: [u64; Fault::ALL.len()],
    pub faults_in_calibration: u64,
    pub faults_while_braking: u64,
    pub answers: [u64; 3],
    /// The largest [`RunReport::max_overrun_deg`] and its seed.
    pub max_overrun: (f64, u64),
    /// The most CPU time a cycle's work took [ns].
    pub max_work_ns: u64,
    pub bus_frames_hit: u64,
    /// Runs whose cycle went over its CPU budget once but not when the seed ran again (the
    /// machine's, not the controller's: a virtual machine's stolen time counts as the
    /// thread's CPU time): `(seed, the violation)`. The rerun's report is the run's.
    pub budget_noise: Vec<(u64, String)>,
    /// The failing runs, by seed: every quiet phase that failed, and the run that broke a
    /// per-cycle invariant (the campaign stops at it unless it keeps going; with several jobs,
    /// the runs under way finish first).
    pub failures: Vec<RunReport>,
}

impl CampaignReport {
    fn add(&mut self, r: &RunReport) {
        self.runs += 1;
        self.simulated_s += r.simulated_s;
        for (a, b) in self.modes_reached.iter_mut().zip(r.modes_reached) {
            *a += b;
        }
        for (a, b) in self.faults_started.iter_mut().zip(r.faults_started) {
            *a += b;
        }
        self.faults_in_calibration += r.faults_in_calibration;
        self.faults_while_braking += r.faults_while_braking;
        for (a, b) in self.answers.iter_mut().zip(r.answers) {
            *a += b;
        }
        self.max_work_ns = self.max_work_ns.max(r.max_work_ns);
        if r.max_overrun_deg > self.max_overrun.0 {
            self.max_overrun = (r.max_overrun_deg, r.seed);
        }
        let b = r.bus;
        self.bus_frames_hit += b.lost_tx
            + b.lost_rx
            + b.corrupted
            + b.duplicated
            + b.delayed
            + b.heartbeats_lost
            + b.syncs_stuck;
        if r.violation.is_some() {
            self.failures.push(r.clone());
        }
    }

    /// The "sometimes" assertions: what no run reached (empty: all reached).
    pub fn never_reached(&self) -> Vec<String> {
        let mut out = Vec::new();
        for m in Mode::ALL {
            if self.modes_reached[*m as usize] == 0 {
                out.push(format!("mode {m}"));
            }
        }
        for f in Fault::ALL {
            if self.faults_started[f.index()] == 0 {
                out.push(format!("fault {}", f.name()));
            }
        }
        if self.faults_in_calibration == 0 {
            out.push("a fault during calibration".into());
        }
        if self.faults_while_braking == 0 {
            out.push("a fault while braking in ERROR".into());
        }
        out
    }

    /// Simulated seconds per wall-clock second.
    pub fn speed(&self) -> f64 {
        self.simulated_s / self.wall_s.max(1e-9)
    }

    pub fn summary(&self) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{} runs, {:.0} simulated s ({:.2} h) in {:.1} s wall: {:.0} simulated s per s",
            self.runs,
            self.simulated_s,
            self.simulated_s / 3600.0,
            self.wall_s,
            self.speed()
        );
        let _ = write!(s, "modes (cycles):");
        for m in Mode::ALL {
            let _ = write!(s, " {m} {}", self.modes_reached[*m as usize]);
        }
        let _ = write!(s, "\nfaults started:");
        for f in Fault::ALL {
            let _ = write!(s, " {} {}", f.name(), self.faults_started[f.index()]);
        }
        let _ = write!(
            s,
            "\nfaults during calibration {}, while braking {}; frames hit by bus faults {}\nanswers: OK {}, refused {}, failed {}\nfurthest beyond a software limit while responsible: {:.3} deg (seed {}; allowed {LIMIT_OVERRUN_DEG} deg)\nthe longest cycle's work (controller and simulation): {} us of CPU time",
            self.faults_in_calibration,
            self.faults_while_braking,
            self.bus_frames_hit,
            self.answers[0],
            self.answers[1],
            self.answers[2],
            self.max_overrun.0,
            self.max_overrun.1,
            self.max_work_ns / 1000
        );
        for (seed, v) in &self.budget_noise {
            let _ = write!(
                s,
                "\nseed {seed}: over the CPU budget once, not when run again (counted as the machine's): {v}"
            );
        }
        s
    }
}

/// One run, judged as a campaign judges it: a run that breaks only the CPU budget is run
/// again, up to [`MAX_RERUNS`] times, until the overrun comes back at the same cycle (the
/// controller's work: the last run's report says so) or the run passes the budget (the
/// machine's noise: a VM's stolen time, a page fault). Returns the last run's report and the
/// overruns that did not come back. Tests that run seeds use it too, so that a busy machine
/// does not fail them.
pub fn run_judged(o: &RunOptions) -> (RunReport, Vec<Violation>) {
    let over_budget = |r: &RunReport| {
        r.violation
            .as_ref()
            .filter(|v| invariant_of(&v.message) == "CPU time")
            .cloned()
    };
    let mut r = run(o);
    let mut seen = Vec::new();
    let mut next = over_budget(&r);
    while let Some(v) = next.take() {
        if seen.contains(&v) || seen.len() == MAX_RERUNS {
            break;
        }
        seen.push(v);
        r = run(o);
        next = over_budget(&r);
    }
    if r.violation.as_ref().is_some_and(|v| seen.contains(v)) {
        // The overrun came back: the controller's, and the report says so.
        seen.clear();
    }
    (r, seen)
}

/// Where a campaign stands after one more run, for [`campaign_with`]'s observer.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    /// Runs finished so far, this one included.
    pub runs: u64,
    /// Simulated seconds spent so far, this run included.
    pub simulated_s: f64,
    /// Wall-clock seconds since the campaign began.
    pub wall_s: f64,
}

/// Run the campaign.
pub fn campaign(opts: &CampaignOptions) -> CampaignReport {
    campaign_with(opts, |_, _| {})
}

/// Run the campaign, telling `observe` of every finished run (its report, judged as in the
/// campaign's own report) and where the campaign stands: a long campaign can show failing
/// seeds as they come, not only at its end. Called from the campaign's threads, one run at a
/// time.
pub fn campaign_with(
    opts: &CampaignOptions,
    observe: impl Fn(&RunReport, Progress) + Sync,
) -> CampaignReport {
    let next = AtomicU64::new(opts.first_seed);
    let spent_ms = AtomicU64::new(0);
    let stop = AtomicBool::new(false);
    let total = Mutex::new(CampaignReport::default());
    let t0 = Instant::now();
    std::thread::scope(|scope| {
        for _ in 0..opts.jobs.max(1) {
            scope.spawn(|| {
                while !stop.load(Ordering::Relaxed)
                    && (spent_ms.load(Ordering::Relaxed) as f64) < opts.budget_s * 1e3
                {
                    let seed = next.fetch_add(1, Ordering::Relaxed);
                    let mut o = RunOptions::new(seed, opts.run_s);
                    o.planted = opts.planted;
                    let (r, noise) = run_judged(&o);
                    if !noise.is_empty() {
                        let mut t = total.lock().expect("no thread panicked");
                        for v in &noise {
                            t.budget_noise.push((seed, v.to_string()));
                        }
                    }
                    spent_ms.fetch_add((r.simulated_s * 1e3) as u64, Ordering::Relaxed);
                    if !opts.keep_going && r.violation.as_ref().is_some_and(|v| !v.quiet_phase) {
                        stop.store(true, Ordering::Relaxed);
                    }
                    let mut t = total.lock().expect("no thread panicked");
                    t.add(&r);
                    let progress = Progress {
                        runs: t.runs,
                        simulated_s: t.simulated_s,
                        wall_s: t0.elapsed().as_secs_f64(),
                    };
                    observe(&r, progress);
                }
            });
        }
    });
    let mut report = total.into_inner().expect("no thread panicked");
    report.wall_s = t0.elapsed().as_secs_f64();
    report.failures.sort_by_key(|r| r.seed);
    report.budget_noise.sort();
    report
}
