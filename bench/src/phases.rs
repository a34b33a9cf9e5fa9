//! The phases of a run, each adding its rows (figure, target, verdict) and notes to the sheet.

use crate::Args;
use crate::client::{Client, HOLD, STATUS, STATUS_DETAIL, is_error};
use crate::cyclictest::Cyclictest;
use crate::error::BenchError;
use crate::report::{Latency, Row, Verdict, latency_table, ratio, rt_latency, us};
use crate::rtt::{Flood, WARM_UP, hold_under_flood, pipelined, pvt_batch, sequential};
use crate::run::Plan;
use crate::stats::Summary;
use crate::torque::LoopOutcome;
use crate::{shm, stall, torque};
use mcm_shared::config::RobotConfig;
use mcm_shared::protocol::MAX_COMMAND_BYTES;
use mcm_shared::service::ServiceNames;
use std::net::SocketAddr;
use std::time::Duration;

/// What the phases share: the MCM under test, a connection to it, and the results so far.
pub struct Bench<'a> {
    pub args: &'a Args,
    pub plan: Plan,
    pub cfg: RobotConfig,
    pub names: ServiceNames,
    pub json: SocketAddr,
    pub gateway_pid: i32,
    pub period_us: u64,
    pub period_s: f64,
    /// Axis 6's torque per ampere [Nm/A].
    pub kt6: f64,
    /// A connection kept open for `status` and `hold` between the phases.
    pub c: Client,
    pub rows: Vec<Row>,
    pub notes: Vec<String>,
    /// The wake-up latency table (empty when that phase did not run).
    pub latency_text: String,
}

pub fn step(what: &str) {
    eprintln!("mcm-bench: {what}");
}

/// Wake-up latency of mcm-rt beside cyclictest at the same period, priority and CPU.
pub fn latency(b: &mut Bench) -> Result<(), BenchError> {
    // 1. Wake-up latency beside cyclictest, same period, priority and CPU.
    let (prio, cpu) = (b.cfg.cycle.priority, b.cfg.cycle.cpu);
    step(&format!(
        "wake-up latency: {} s, cyclictest -p{prio} -a{cpu} -i{}",
        b.plan.latency_secs, b.period_us
    ));
    let ct = if b.args.no_cyclictest {
        b.notes.push("cyclictest skipped (--no-cyclictest)".into());
        None
    } else {
        match Cyclictest::start(prio, cpu, b.period_us, b.plan.latency_secs)
            .and_then(|ct| ct.finish())
        {
            Ok(r) => Some(Latency::from_cyclictest(&r)),
            Err(e) => {
                b.notes.push(e.to_string());
                None
            }
        }
    };
    if b.args.no_cyclictest {
        std::thread::sleep(Duration::from_secs(b.plan.latency_secs));
    }
    let detail = b.c.status(&STATUS_DETAIL)?;
    let timing = detail
        .detail
        .map(|d| d.timing)
        .ok_or_else(|| BenchError::Setup("the detailed status has no detail".into()))?;
    let (since, recent) = rt_latency(&timing);
    // The ratio compares like with like: mcm-rt since its start (the whole cyclictest window
    // plus start-up and calibration, thousands of cycles) against cyclictest's whole run. The
    // recent window holds only its last 10 s, 2000 cycles at 200 Hz, where p99.9 is the second
    // worst cycle: shown in the table, not used for the verdict.
    let rt = since;
    b.latency_text = latency_table(&since, recent.as_ref(), ct.as_ref());
    let p999_ratio = ratio(rt.p99_9, ct.as_ref().and_then(|c| c.p99_9));
    b.rows.push(Row::new(
        "wake-up p99.9 mcm-rt / cyclictest",
        p999_ratio.map_or("n/a".into(), |r| format!("{r:.2}")),
        "<= 1.5",
        Verdict::at_most(p999_ratio, 1.5),
    ));
    b.rows.push(Row::info(
        "mcm-rt overruns / work max / over budget",
        format!(
            "{} / {} / {}",
            timing.overruns,
            us(Some(timing.work_max_us)),
            timing.over_budget
        ),
    ));
    Ok(())
}

/// `status` round trip on one connection, one at a time and pipelined.
pub fn status(b: &mut Bench) -> Result<(), BenchError> {
    // 2. status round trip on one connection.
    step("status round trip");
    match sequential(&mut b.c, &STATUS, b.plan.status, b.plan.budget, WARM_UP) {
        Ok(s) => {
            let m = s.summary;
            b.rows.push(Row::new(
                "status RTT p50 (one at a time)",
                us(m.map(|m| m.p50_us)),
                "< 150 us",
                Verdict::below(m.map(|m| m.p50_us), 150.0),
            ));
            b.rows.push(Row::new(
                "status RTT p99 (one at a time)",
                us(m.map(|m| m.p99_us)),
                "< 1 ms",
                Verdict::below(m.map(|m| m.p99_us), 1000.0),
            ));
            b.rows.push(Row::info(
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
        Err(e) => failed(&mut b.rows, "status RTT (one at a time)", &e),
    }
    match pipelined(&mut b.c, b.plan.pipelined, b.plan.budget) {
        Ok(p) => {
            b.rows.push(Row::new(
                "status results/s (pipelined, 1 conn.)",
                format!("{:.0}/s", p.rate),
                ">= 5000/s",
                Verdict::at_least(Some(p.rate), 5000.0),
            ));
            b.rows.push(Row::info(
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
        Err(e) => failed(&mut b.rows, "status results/s (pipelined)", &e),
    }
    Ok(())
}

/// `hold` acknowledgement, idle and while other connections flood `pvt_points`.
pub fn hold(b: &mut Bench) -> Result<(), BenchError> {
    // 3. hold acknowledgement, idle and under a pvt_points flood.
    let hold_limit_us = b.period_us as f64 + 500.0;
    let hold_target = format!("<= {} us (1 cycle + 0.5 ms)", hold_limit_us);
    step("hold acknowledgement (idle)");
    match sequential(&mut b.c, &HOLD, b.plan.holds, b.plan.budget, WARM_UP) {
        Ok(s) => {
            hold_rows(
                &mut b.rows,
                "idle",
                &s.summary,
                s.errors,
                &hold_target,
                hold_limit_us,
            );
            after_cycle_row(&mut b.rows, "idle", &s.after_cycle);
        }
        Err(e) => failed(&mut b.rows, "hold ack (idle)", &e),
    }
    step(&format!(
        "hold acknowledgement with {} connections flooding pvt_points",
        b.args.flood_clients
    ));
    match flood_phase(&mut b.c, b.json, b.args.flood_clients, &b.plan) {
        Ok((s, batches)) => {
            hold_rows(
                &mut b.rows,
                &format!("{} flooding", b.args.flood_clients),
                &s.summary,
                s.errors,
                &hold_target,
                hold_limit_us,
            );
            after_cycle_row(
                &mut b.rows,
                &format!("{} flooding", b.args.flood_clients),
                &s.after_cycle,
            );
            b.rows.push(Row::info(
                "pvt_points batches answered during the flood",
                batches.to_string(),
            ));
        }
        Err(e) => failed(&mut b.rows, "hold ack (flood)", &e),
    }
    Ok(())
}

/// The torque loop over TCP and over shared memory.
pub fn torque(b: &mut Bench) -> Result<(), BenchError> {
    // 4. The torque loop over TCP and over shared memory.
    step(&format!(
        "torque loop over TCP, {} cycles",
        b.plan.torque_cycles
    ));
    let r = torque::tcp_loop(b.json, b.plan.torque_cycles, b.period_s, b.kt6);
    loop_rows(&mut b.rows, &mut b.notes, "TCP", r, b.plan.torque_cycles);
    let _ = b.c.ok(&HOLD);
    step(&format!(
        "torque loop over shared memory, {} cycles",
        b.plan.torque_cycles
    ));
    let r = shm::shm_loop(&b.names, b.plan.torque_cycles, b.kt6, &mut b.notes);
    loop_rows(&mut b.rows, &mut b.notes, "shm", r, b.plan.torque_cycles);
    let _ = b.c.ok(&HOLD);
    Ok(())
}

/// Replies across a gateway stall.
pub fn stall(b: &mut Bench) -> Result<(), BenchError> {
    // 5. Replies across a gateway stall.
    step(&format!(
        "gateway stopped for {} ms under {} busy clients and {} flooding",
        b.args.stall_ms, b.args.stall_clients, b.args.stall_flood
    ));
    let stalled = flood_batch(&mut b.c).and_then(|batch| {
        stall::run(
            b.json,
            b.gateway_pid,
            b.args.stall_clients,
            Duration::from_millis(b.args.stall_ms),
            Duration::from_secs(2),
            b.args.stall_flood,
            batch,
        )
    });
    match stalled {
        Ok(s) => {
            b.rows.push(Row::new(
                format!("replies lost, gateway stopped {} ms", b.args.stall_ms),
                format!("{} of {}", s.lost(), s.sent()),
                "0",
                Verdict::at_most(Some(s.lost() as f64), 0.0),
            ));
            b.rows.push(Row::new(
                "errors across the stall",
                s.errors().to_string(),
                "0",
                Verdict::at_most(Some(s.errors() as f64), 0.0),
            ));
            b.notes.push(format!(
                "stall: {} pvt_points batches answered to the {} flooding connections",
                s.flood_batches, b.args.stall_flood
            ));
            for (i, n) in s.clients.iter().enumerate() {
                b.notes.push(format!(
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
        Err(e) => failed(&mut b.rows, "replies across a gateway stall", &e),
    }
    Ok(())
}

fn errors_text(n: u64) -> String {
    if n == 0 {
        String::new()
    } else {
        format!(", {n} ERRORS")
    }
}

pub fn failed(rows: &mut Vec<Row>, what: &str, e: &BenchError) {
    rows.push(Row::new(
        what,
        format!("not measured: {e}"),
        "",
        Verdict::NotMeasured,
    ));
}

/// Where the time of a `hold` goes: from the start of the cycle that answered to the result
/// read by the client (the state's `time` and the client's clock are both `CLOCK_MONOTONIC`).
fn after_cycle_row(rows: &mut Vec<Row>, when: &str, m: &Option<Summary>) {
    rows.push(Row::info(
        format!("hold: cycle start to result p50 / p99 ({when})"),
        format!("{} / {}", us(m.map(|m| m.p50_us)), us(m.map(|m| m.p99_us))),
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
    let pos = c.status(&STATUS)?.axis_states.position;
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
    let v = c.request(&HOLD)?;
    c.set_read_timeout(crate::client::READ_WAIT)?;
    if is_error(&v) {
        return Err(BenchError::Protocol {
            command: "hold (after the flood)".into(),
            answer: v.to_value().to_string(),
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
