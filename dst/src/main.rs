//! `mcm-dst`: run one seed (`--seed N`, replayed bit for bit) or a campaign over many seeds
//! (`--hours H --jobs J`). See `docs/testing.md`, "Deterministic simulation testing".

use mcm_dst::campaign::{CampaignOptions, campaign_with};
use mcm_dst::cli;
use mcm_dst::hash::first_divergence;
use mcm_dst::run::{RunOptions, planted_name, run};
use mcm_dst::script::{Script, replay};
use mcm_dst::shrink::{invariant_of, shrink};
use mcm_shared::alloc_count::CountingAlloc;
use std::process::ExitCode;
use std::sync::atomic::{AtomicU64, Ordering};

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

/// The commit this binary was built from (`build.rs`), and whether the checkout it was built
/// in has uncommitted changes now (looked at when a failure is reported: the build script
/// cannot see edits, and a replay needs to know that the commit alone may not be the code).
fn commit() -> String {
    let dirty = std::process::Command::new("git")
        .args(["status", "--porcelain", "--untracked-files=no"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .filter(|o| o.status.success())
        .is_some_and(|o| !o.stdout.is_empty());
    let commit = env!("MCM_DST_COMMIT");
    if dirty {
        format!("{commit}; its checkout has uncommitted changes now")
    } else {
        commit.to_string()
    }
}

fn main() -> ExitCode {
    let args = match cli::parse(std::env::args().skip(1)) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("mcm-dst: {e}\n{}", cli::USAGE);
            return ExitCode::from(2);
        }
    };
    if args.help {
        println!("{}", cli::USAGE);
        return ExitCode::SUCCESS;
    }
    let cli::Args {
        seed,
        seconds,
        hours,
        jobs,
        first_seed,
        planted,
        replay: replay_file,
        shrink_replays,
        keep_going,
        ..
    } = args;
    if let Some(file) = replay_file {
        return replay_script(&file, seconds);
    }
    if let Some(seed) = seed {
        let mut o = RunOptions::new(seed, seconds);
        o.planted = planted;
        let t0 = std::time::Instant::now();
        let a = run(&o);
        let wall = t0.elapsed().as_secs_f64();
        let b = run(&o);
        println!(
            "seed {seed}: {} cycles, {:.0} simulated s in {wall:.2} s ({:.0} simulated s per s), hash {:016x}",
            a.cycles,
            a.simulated_s,
            a.simulated_s / wall,
            a.hash
        );
        println!(
            "swarm: {} clients, faults {:?}",
            a.swarm.clients,
            a.swarm.fault_names()
        );
        println!(
            "modes (cycles): {:?}; answers OK/refused/failed {:?}; recovery {:?} cycles; furthest beyond a software limit {:.3} deg",
            a.modes_reached, a.answers, a.recovery_cycles, a.max_overrun_deg
        );
        if a.hash != b.hash || a.violation != b.violation {
            let at = first_divergence(&a.checkpoints, &b.checkpoints)
                .map_or("no cycle (the violations differ)".into(), |k| {
                    format!("cycle {k}")
                });
            eprintln!(
                "NOT DETERMINISTIC: seed {seed} gave hash {:016x} then {:016x}; first different: {at}",
                a.hash, b.hash
            );
            return ExitCode::FAILURE;
        }
        println!("replayed: the same hash twice");
        return match a.violation {
            None => ExitCode::SUCCESS,
            Some(v) => {
                eprintln!("FAILED seed {seed} (commit {}): {v}", commit());
                // A script replays the per-cycle invariants; the quiet phase's recovery and
                // the commands left unanswered at the end are judged on the whole run only.
                if !v.quiet_phase && invariant_of(&v.message) != "another invariant" {
                    write_shrunk(&a.script, &v, shrink_replays);
                }
                ExitCode::FAILURE
            }
        };
    }
    let budget_s = hours * 3600.0;
    // While it runs, a campaign says on stderr each failing run as it comes and where it
    // stands every twentieth of its budget: a long campaign cut short still tells.
    let steps_shown = AtomicU64::new(0);
    let options = CampaignOptions {
        first_seed,
        budget_s,
        run_s: seconds,
        jobs,
        planted,
        keep_going,
    };
    let r = campaign_with(&options, |run, at| {
        if let Some(v) = &run.violation {
            eprintln!("failing run, seed {}: {v}", run.seed);
        }
        let step = ((at.simulated_s / budget_s * PROGRESS_STEPS as f64) as u64).min(PROGRESS_STEPS);
        if step > steps_shown.fetch_max(step, Ordering::Relaxed) {
            eprintln!(
                "campaign: {:.1} of {hours} simulated h, {} runs, {:.0} s wall",
                at.simulated_s / 3600.0,
                at.runs,
                at.wall_s
            );
        }
    });
    println!("{}", r.summary());
    let mut ok = true;
    let planted_arg = planted.map_or(String::new(), |p| {
        format!(" --planted-bug {}", planted_name(p))
    });
    for f in &r.failures {
        ok = false;
        eprintln!(
            "FAILED seed {} (commit {}): {}\n  replay: mcm-dst --seed {} --seconds {seconds}{planted_arg}",
            f.seed,
            commit(),
            f.violation.as_ref().expect("a failure"),
            f.seed
        );
    }
    let never = r.never_reached();
    if !never.is_empty() {
        ok = false;
        eprintln!("never reached: {}", never.join(", "));
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// How many progress lines a campaign prints on its way (one every twentieth of its budget).
const PROGRESS_STEPS: u64 = 20;

/// Shrink the failing run's script and write what is left to `mcm-dst-seed-N.script`.
fn write_shrunk(script: &Script, v: &mcm_dst::invariants::Violation, max_replays: u32) {
    let t0 = std::time::Instant::now();
    let Some(s) = shrink(script, v, max_replays) else {
        eprintln!(
            "NOT SHRUNK: the run's own script does not break the same invariant when replayed (a bug of mcm-dst's recording)"
        );
        return;
    };
    let file = format!("mcm-dst-seed-{}.script", script.seed);
    let budget = if s.budget_spent {
        " (the replay budget ran out: --shrink-replays)"
    } else {
        ""
    };
    eprintln!(
        "shrunk in {:.1} s, {} replays{budget}: {} inputs of {} up to the failure are needed; the shrunk run fails at cycle {}: {}",
        t0.elapsed().as_secs_f64(),
        s.replays,
        s.script.events.len(),
        s.inputs_before,
        s.violation.cycle,
        s.violation.message
    );
    match std::fs::write(&file, s.script.to_string()) {
        Ok(()) => eprintln!("  written to {file}; replay: mcm-dst --replay {file}"),
        Err(e) => eprintln!("  cannot write {file}: {e}"),
    }
}

/// Replay a script file for `seconds` past its last input.
fn replay_script(file: &str, seconds: f64) -> ExitCode {
    let text = match std::fs::read_to_string(file) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("mcm-dst: cannot read {file}: {e}");
            return ExitCode::from(2);
        }
    };
    let script: Script = match text.parse() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("mcm-dst: {file}: {e}");
            return ExitCode::from(2);
        }
    };
    let last = script.events.last().map_or(0, |e| e.cycle);
    // The runs' configuration is the P-Rob2's (`run::config` draws only offsets and the pose).
    let rate = mcm_dst::rate::Rate::of(&mcm_shared::config::RobotConfig::prob2_default());
    let cycles = last + rate.cycles(seconds);
    match replay(&script, cycles) {
        None => {
            println!(
                "{file}: seed {}, {} inputs, {cycles} cycles replayed: no invariant broken",
                script.seed,
                script.events.len()
            );
            ExitCode::SUCCESS
        }
        Some(v) => {
            eprintln!("FAILED {file} (commit {}): {v}", commit());
            ExitCode::FAILURE
        }
    }
}
