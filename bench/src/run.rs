//! One benchmark run: start the MCM, measure phase after phase, stop it, print the table.
//! A phase that fails is reported in its rows (not measured) and the run goes on.

use crate::Args;
use crate::client::{Client, HOLD, STATUS, STATUS_DETAIL, is_error};
use crate::cyclictest::Cyclictest;
use crate::error::BenchError;
use crate::mcm::{Mcm, locate};
use crate::report::{Latency, Row, Verdict, latency_table, ratio, rt_latency, table, us};
use crate::rtt::{Flood, WARM_UP, hold_under_flood, pipelined, pvt_batch, sequential};
use crate::stats::Summary;
use crate::torque::LoopOutcome;
use crate::{shm, stall, torque};
use mcm_shared::config::RobotConfig;
use mcm_shared::service::ServiceNames;
use std::time::{Duration, Instant};

/// The phases, in the order they run.
const PHASES: [&str; 5] = ["latency", "status", "hold", "torque", "stall"];

/// The gateway's limit of one command line (`gateway/src/framing.rs`).
const MAX_COMMAND_BYTES: usize = 64 * 1024;

/// How many samples each phase takes, and its time budget.
struct Plan {
    latency_secs: u64,
    status: usize,
    pipelined: usize,
    holds: usize,
    torque_cycles: u64,
    budget: Duration,
}

impl Plan {
    fn new(a: &Args) -> Plan {
        let q = a.quick;
        Plan {
            latency_secs: a.latency_secs.unwrap_or(if q { 10 } else { 60 }),
            status: if q { 2_000 } else { 10_000 },
            pipelined: if q { 5_000 } else { 50_000 },
            holds: if q { 200 } else { 1_000 },
            torque_cycles: a.torque_cycles.unwrap_or(if q { 1_000 } else { 10_000 }),
            budget: Duration::from_secs(if q { 15 } else { 60 }),
        }
    }
}

fn step(what: &str) {
    eprintln!("mcm-bench: {what}");
}

/// Run everything; `Ok(true)` when every target passed.
pub fn run(args: &Args) -> Result<bool, BenchError> {
    for p in &args.only {
        if !PHASES.contains(&p.as_str()) {
            return Err(BenchError::Setup(format!(
                "--only {p:?} is not a phase; the phases are {}",
                PHASES.join(", ")
            )));
        }
    }
    let cfg = match &args.config {
        Some(path) => RobotConfig::from_file(path)
            .map_err(|e| BenchError::Start(format!("config {}: {e}", path.display())))?,
        None => RobotConfig::prob2_default(),
    };
    let period_ns = cfg.cycle_period_ns();
    let period_us = period_ns / 1_000;
    let period_s = period_ns as f64 / 1e9;
    let kt6 = cfg.axes[5].torque_per_amp();
    let plan = Plan::new(args);
    let binary = locate(args.mcm.as_deref())?;
    let instance = format!("bench-{}", std::process::id());
    let names = ServiceNames::new(&instance).map_err(|e| BenchError::Start(e.to_string()))?;
    step(&format!(
        "starting {} --instance {instance}",
        binary.display()
    ));
    let mcm = Mcm::start(&binary, &instance, args.config.as_deref())?;
    let mut rows = Vec::new();
    let mut notes = Vec::new();
    let started = Instant::now();
    let mut lat_text = String::new();

    // Ready: drives online, calibrated (the torque loops need it), in HOLD.
    let mut c = Client::connect(mcm.json)?;
    let wait = Duration::from_secs(60);
    c.wait_status("all drives online", wait, |s| {
        s["detail"]["drive_online"]
            .as_array()
            .is_some_and(|a| a.iter().all(|x| x == true))
    })?;
    step("calibrating the simulated arm");
    {
        // On a connection of its own: a motion command makes its client the owner of motion,
        // and ownership ends when the connection closes; the loops later need to own it.
        let mut cal = Client::connect(mcm.json)?;
        cal.set_read_timeout(Duration::from_secs(180))?;
        cal.ok(r#"{"command":"calibrate"}"#)?;
        cal.ok(HOLD)?;
    }
    c.ok(HOLD)?;
    let realtime = c.ok(STATUS_DETAIL)?["detail"]["timing"]["realtime"] == true;
    if !realtime {
        notes.push(
            "mcm-rt runs WITHOUT real-time scheduling (not root?): latency figures mean little"
                .into(),
        );
    }

    if args.wants("latency") {
        // 1. Wake-up latency beside cyclictest, same period, priority and CPU.
        let (prio, cpu) = (cfg.cycle.priority, cfg.cycle.cpu);
        step(&format!(
            "wake-up latency: {} s, cyclictest -p{prio} -a{cpu} -i{period_us}",
            plan.latency_secs
        ));
        let ct = if args.no_cyclictest {
            notes.push("cyclictest skipped (--no-cyclictest)".into());
            None
        } else {
            match Cyclictest::start(prio, cpu, period_us, plan.latency_secs)
                .and_then(|ct| ct.finish())
            {
                Ok(r) => Some(Latency::from_cyclictest(&r)),
                Err(e) => {
                    notes.push(e.to_string());
                    None
                }
            }
        };
        if args.no_cyclictest {
            std::thread::sleep(Duration::from_secs(plan.latency_secs));
        }
        let detail = c.ok(STATUS_DETAIL)?;
        let (since, recent) = rt_latency(&detail);
        let rt = recent.unwrap_or(since);
        lat_text = latency_table(&since, recent.as_ref(), ct.as_ref());
        let p999_ratio = ratio(rt.p99_9, ct.as_ref().and_then(|c| c.p99_9));
        rows.push(Row::new(
            "wake-up p99.9 mcm-rt / cyclictest",
            p999_ratio.map_or("n/a".into(), |r| format!("{r:.2}")),
            "<= 1.5",
            Verdict::at_most(p999_ratio, 1.5),
        ));
        let t = &detail["detail"]["timing"];
        rows.push(Row::info(
            "mcm-rt overruns / work max / over budget",
            format!(
                "{} / {} / {}",
                t["overruns"],
                us(t["work_max_us"].as_f64()),
                t.get("over_budget").map_or("n/a".into(), |v| v.to_string())
            ),
        ));
    }

    if args.wants("status") {
        // 2. status round trip on one connection.
        step("status round trip");
        match sequential(&mut c, STATUS, plan.status, plan.budget, WARM_UP) {
            Ok(s) => {
                let m = s.summary;
                rows.push(Row::new(
                    "status RTT p50 (one at a time)",
                    us(m.map(|m| m.p50_us)),
                    "< 150 us",
                    Verdict::below(m.map(|m| m.p50_us), 150.0),
                ));
                rows.push(Row::new(
                    "status RTT p99 (one at a time)",
                    us(m.map(|m| m.p99_us)),
                    "< 1 ms",
                    Verdict::below(m.map(|m| m.p99_us), 1000.0),
                ));
                rows.push(Row::info(
                    "status one at a time: rate, max, n",
                    format!(
                        "{:.0}/s, {}, {}{}",
                        s.rate,
                        us(m.map(|m| m.max_us)),
                        m.map_or(0, |m| m.count),
                        errors_text(s.errors)
                    ),
                ));
            }
            Err(e) => failed(&mut rows, "status RTT (one at a time)", &e),
        }
        match pipelined(&mut c, plan.pipelined, plan.budget) {
            Ok(p) => {
                rows.push(Row::new(
                    "status results/s (pipelined, 1 conn.)",
                    format!("{:.0}/s", p.rate),
                    ">= 5000/s",
                    Verdict::at_least(Some(p.rate), 5000.0),
                ));
                rows.push(Row::info(
                    "status pipelined RTT p50 / p99, n",
                    format!(
                        "{} / {}, {}{}",
                        us(p.summary.map(|m| m.p50_us)),
                        us(p.summary.map(|m| m.p99_us)),
                        p.summary.map_or(0, |m| m.count),
                        errors_text(p.errors)
                    ),
                ));
            }
            Err(e) => failed(&mut rows, "status results/s (pipelined)", &e),
        }
    }

    if args.wants("hold") {
        // 3. hold acknowledgement, idle and under a pvt_points flood.
        let hold_limit_us = period_us as f64 + 500.0;
        let hold_target = format!("<= {} us (1 cycle + 0.5 ms)", hold_limit_us);
        step("hold acknowledgement (idle)");
        match sequential(&mut c, HOLD, plan.holds, plan.budget, WARM_UP) {
            Ok(s) => hold_rows(
                &mut rows,
                "idle",
                &s.summary,
                s.errors,
                &hold_target,
                hold_limit_us,
            ),
            Err(e) => failed(&mut rows, "hold ack (idle)", &e),
        }
        step(&format!(
            "hold acknowledgement with {} connections flooding pvt_points",
            args.flood_clients
        ));
        match flood_phase(&mut c, mcm.json, args.flood_clients, &plan) {
            Ok((s, batches)) => {
                hold_rows(
                    &mut rows,
                    &format!("{} flooding", args.flood_clients),
                    &s.summary,
                    s.errors,
                    &hold_target,
                    hold_limit_us,
                );
                rows.push(Row::info(
                    "pvt_points batches answered during the flood",
                    batches.to_string(),
                ));
            }
            Err(e) => failed(&mut rows, "hold ack (flood)", &e),
        }
    }

    if args.wants("torque") {
        // 4. The torque loop over TCP and over shared memory.
        step(&format!(
            "torque loop over TCP, {} cycles",
            plan.torque_cycles
        ));
        let r = torque::tcp_loop(mcm.json, plan.torque_cycles, period_s, kt6);
        loop_rows(&mut rows, &mut notes, "TCP", r, plan.torque_cycles);
        let _ = c.ok(HOLD);
        step(&format!(
            "torque loop over shared memory, {} cycles",
            plan.torque_cycles
        ));
        let r = shm::shm_loop(&names, plan.torque_cycles, kt6, &mut notes);
        loop_rows(&mut rows, &mut notes, "shm", r, plan.torque_cycles);
        let _ = c.ok(HOLD);
    }

    if args.wants("stall") {
        // 5. Replies across a gateway stall.
        step(&format!(
            "gateway stopped for {} ms under {} busy clients and {} flooding",
            args.stall_ms, args.stall_clients, args.stall_flood
        ));
        let stalled = flood_batch(&mut c).and_then(|batch| {
            stall::run(
                mcm.json,
                mcm.gateway_pid,
                args.stall_clients,
                Duration::from_millis(args.stall_ms),
                Duration::from_secs(2),
                args.stall_flood,
                batch,
            )
        });
        match stalled {
            Ok(s) => {
                rows.push(Row::new(
                    format!("replies lost, gateway stopped {} ms", args.stall_ms),
                    format!("{} of {}", s.lost(), s.sent()),
                    "0",
                    Verdict::at_most(Some(s.lost() as f64), 0.0),
                ));
                rows.push(Row::new(
                    "errors across the stall",
                    s.errors().to_string(),
                    "0",
                    Verdict::at_most(Some(s.errors() as f64), 0.0),
                ));
                notes.push(format!(
                    "stall: {} pvt_points batches answered to the {} flooding connections",
                    s.flood_batches, args.stall_flood
                ));
                for (i, n) in s.clients.iter().enumerate() {
                    notes.push(format!(
                        "stall client {i} ({}): sent {}, ok {}, errors {}, lost {}{}",
                        n.command,
                        n.sent,
                        n.ok,
                        n.errors,
                        n.lost,
                        n.first_error
                            .as_ref()
                            .map_or(String::new(), |e| format!("; first error: {e}"))
                    ));
                }
            }
            Err(e) => failed(&mut rows, "replies across a gateway stall", &e),
        }
    }

    drop(c);
    step("stopping the MCM");
    mcm.stop();
    println!(
        "MCM command path benchmark{} ({} s, period {} us, instance {instance})",
        if args.quick { " --quick" } else { "" },
        started.elapsed().as_secs(),
        period_us
    );
    println!();
    if !lat_text.is_empty() {
        print!("{lat_text}");
        println!();
    }
    print!("{}", table(&rows));
    if !notes.is_empty() {
        println!();
        for n in &notes {
            println!("note: {n}");
        }
    }
    Ok(!rows
        .iter()
        .any(|r| r.verdict == Verdict::Fail || r.verdict == Verdict::NotMeasured))
}

fn errors_text(n: u64) -> String {
    if n == 0 {
        String::new()
    } else {
        format!(", {n} ERRORS")
    }
}

fn failed(rows: &mut Vec<Row>, what: &str, e: &BenchError) {
    rows.push(Row::new(
        what,
        format!("not measured: {e}"),
        "",
        Verdict::NotMeasured,
    ));
}

fn hold_rows(
    rows: &mut Vec<Row>,
    when: &str,
    m: &Option<Summary>,
    errors: u64,
    target: &str,
    limit: f64,
) {
    rows.push(Row::new(
        format!("hold ack p99 ({when})"),
        us(m.map(|m| m.p99_us)),
        target,
        Verdict::at_most(m.map(|m| m.p99_us), limit),
    ));
    rows.push(Row::info(
        format!("hold ack p50 / max, n ({when})"),
        format!(
            "{} / {}, {}{}",
            us(m.map(|m| m.p50_us)),
            us(m.map(|m| m.max_us)),
            m.map_or(0, |m| m.count),
            errors_text(errors)
        ),
    ));
}

/// A 1000-point `pvt_points` batch at the arm's position (refused in HOLD: not in PVT).
fn flood_batch(c: &mut Client) -> Result<String, BenchError> {
    let s = c.ok(STATUS)?;
    let pos: [f64; 6] =
        std::array::from_fn(|i| s["axis_states"]["position"][i].as_f64().unwrap_or(0.0));
    let batch = pvt_batch(1000, pos);
    if batch.len() >= MAX_COMMAND_BYTES {
        return Err(BenchError::Setup(format!(
            "a 1000-point batch at {pos:?} is {} bytes, above the gateway's limit of {MAX_COMMAND_BYTES}",
            batch.len()
        )));
    }
    Ok(batch)
}

fn flood_phase(
    c: &mut Client,
    addr: std::net::SocketAddr,
    clients: usize,
    plan: &Plan,
) -> Result<(crate::rtt::Sequential, u64), BenchError> {
    let flood = Flood::start(addr, clients, flood_batch(c)?)?;
    let measured = hold_under_flood(addr, &flood, plan.holds, plan.budget);
    let batches = flood.stop()?;
    // The gateway may still hold flooded work: one hold through it before going on.
    c.set_read_timeout(Duration::from_secs(120))?;
    let v = c.request(HOLD)?;
    c.set_read_timeout(crate::client::READ_WAIT)?;
    if is_error(&v) {
        return Err(BenchError::Protocol {
            command: "hold (after the flood)".into(),
            answer: v.to_string(),
        });
    }
    Ok((measured?, batches))
}

fn loop_rows(
    rows: &mut Vec<Row>,
    notes: &mut Vec<String>,
    via: &str,
    r: Result<LoopOutcome, BenchError>,
    cycles: u64,
) {
    match r {
        Ok(o) => {
            let t = o.tally;
            let share = (t.answers > 0).then(|| 100.0 * t.on_time_share());
            let target = if via == "TCP" {
                ">= 99.9 %"
            } else {
                ">= 99.9 % (as TCP)"
            };
            rows.push(Row::new(
                format!("torque loop {via}: applied next cycle"),
                share.map_or("n/a".into(), |s| format!("{s:.2} % of {}", t.answers)),
                target,
                if t.answers < cycles {
                    Verdict::Fail
                } else {
                    Verdict::at_least(share, 99.9)
                },
            ));
            rows.push(Row::info(
                format!("torque loop {via}: late / never / unseen / refused"),
                format!("{} / {} / {} / {}", t.late, t.never, t.unobserved, o.errors),
            ));
            notes.push(format!(
                "torque loop {via}: woke on {}; axis-6 compensation {:.3} Nm; repeated states {}{}",
                o.wait_mode,
                o.baseline_nm,
                o.repeats,
                o.ended_early
                    .map_or(String::new(), |e| format!("; ENDED EARLY: {e}"))
            ));
        }
        Err(e) => failed(rows, &format!("torque loop {via}"), &e),
    }
}
