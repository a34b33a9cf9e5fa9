//! The figures of one run, the targets beside them, and the table printed at the end
//! (pure: builds text, does no I/O).

use crate::stats::HistFigure;
use mcm_shared::protocol::results::{RecentTiming, Timing};

/// Wake-up latency figures [µs]; `None` where the source does not report one.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Latency {
    pub p50: Option<f64>,
    pub p99: Option<f64>,
    pub p99_9: Option<f64>,
    pub p99_99: Option<f64>,
    pub max: Option<f64>,
}

impl Latency {
    /// mcm-rt's figures since its start.
    fn since_start(t: &Timing) -> Latency {
        Latency {
            p50: Some(t.latency_p50_us),
            p99: Some(t.latency_p99_us),
            p99_9: Some(t.latency_p99_9_us),
            p99_99: Some(t.latency_p99_99_us),
            max: Some(t.latency_max_us),
        }
    }

    /// mcm-rt's figures over its recent window.
    fn recent(t: &RecentTiming) -> Latency {
        Latency {
            p50: Some(t.latency_p50_us),
            p99: Some(t.latency_p99_us),
            p99_9: Some(t.latency_p99_9_us),
            p99_99: Some(t.latency_p99_99_us),
            max: Some(t.latency_max_us),
        }
    }

    /// The figures of a cyclictest histogram (a percentile beyond its range is left out).
    pub fn from_cyclictest(r: &crate::cyclictest::CyclicResult) -> Latency {
        let p = |q| match r.percentile(q) {
            Some(HistFigure::Us(us)) => Some(us as f64),
            _ => None,
        };
        Latency {
            p50: p(50.0),
            p99: p(99.0),
            p99_9: p(99.9),
            p99_99: p(99.99),
            max: Some(r.max_us as f64),
        }
    }
}

/// mcm-rt's wake-up latency from the timing of a detailed status: the since-start figures
/// (`detail.timing.latency_*_us`) and, when its window holds cycles, the recent window's
/// (`detail.timing.recent.latency_*_us`).
pub fn rt_latency(t: &Timing) -> (Latency, Option<Latency>) {
    let recent = (t.recent.cycles > 0).then(|| Latency::recent(&t.recent));
    (Latency::since_start(t), recent)
}

/// Verdict of one figure against its target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Pass,
    Fail,
    /// The figure could not be measured (missing key, phase failed).
    NotMeasured,
    /// No target for this figure.
    Info,
}

impl Verdict {
    pub fn at_most(figure: Option<f64>, limit: f64) -> Verdict {
        match figure {
            Some(f) if f <= limit => Verdict::Pass,
            Some(_) => Verdict::Fail,
            None => Verdict::NotMeasured,
        }
    }

    pub fn below(figure: Option<f64>, limit: f64) -> Verdict {
        match figure {
            Some(f) if f < limit => Verdict::Pass,
            Some(_) => Verdict::Fail,
            None => Verdict::NotMeasured,
        }
    }

    pub fn at_least(figure: Option<f64>, limit: f64) -> Verdict {
        match figure {
            Some(f) if f >= limit => Verdict::Pass,
            Some(_) => Verdict::Fail,
            None => Verdict::NotMeasured,
        }
    }

    fn word(self) -> &'static str {
        match self {
            Verdict::Pass => "PASS",
            Verdict::Fail => "FAIL",
            Verdict::NotMeasured => "n/a",
            Verdict::Info => "",
        }
    }
}

/// One line of the table.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub what: String,
    pub figure: String,
    pub target: String,
    pub verdict: Verdict,
}

impl Row {
    pub fn new(
        what: impl Into<String>,
        figure: impl Into<String>,
        target: &str,
        verdict: Verdict,
    ) -> Row {
        Row {
            what: what.into(),
            figure: figure.into(),
            target: target.into(),
            verdict,
        }
    }

    pub fn info(what: impl Into<String>, figure: impl Into<String>) -> Row {
        Row::new(what, figure, "", Verdict::Info)
    }
}

/// A duration [µs] for the table: µs below 10 ms, else ms; "n/a" when missing.
pub fn us(v: Option<f64>) -> String {
    match v {
        None => "n/a".into(),
        Some(v) if v < 10_000.0 => format!("{v:.0} us"),
        Some(v) => format!("{:.1} ms", v / 1000.0),
    }
}

/// `a / b` when both are known and `b` is not zero.
pub fn ratio(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) if b > 0.0 => Some(a / b),
        _ => None,
    }
}

fn ratio_text(r: Option<f64>) -> String {
    r.map_or("n/a".into(), |r| format!("{r:.2}"))
}

/// The side-by-side wake-up latency table: mcm-rt since start, over its recent window (when
/// `status` reports one), cyclictest, and the ratio of mcm-rt's figure (the recent one when
/// there is one: it lies inside cyclictest's run) to cyclictest's.
pub fn latency_table(since: &Latency, recent: Option<&Latency>, ct: Option<&Latency>) -> String {
    let none = Latency::default();
    let ct = ct.unwrap_or(&none);
    let rt = recent.unwrap_or(since);
    let recent = recent.unwrap_or(&none);
    let line = |a: &str, b: &str, c: &str, d: &str, e: &str| {
        format!("{a:<8} {b:>14} {c:>14} {d:>12} {e:>8}\n")
    };
    let mut s = line(
        "latency",
        "mcm-rt (start)",
        "mcm-rt (rec.)",
        "cyclictest",
        "ratio",
    );
    let pick = |l: &Latency| [l.p50, l.p99, l.p99_9, l.p99_99, l.max];
    let names = ["p50", "p99", "p99.9", "p99.99", "max"];
    for (i, name) in names.iter().enumerate() {
        let (a, r, b, c) = (pick(since)[i], pick(recent)[i], pick(ct)[i], pick(rt)[i]);
        s += &line(name, &us(a), &us(r), &us(b), &ratio_text(ratio(c, b)));
    }
    s
}

/// The results table.
pub fn table(rows: &[Row]) -> String {
    let w0 = rows.iter().map(|r| r.what.len()).max().unwrap_or(0).max(11);
    let w1 = rows
        .iter()
        .map(|r| r.figure.len())
        .max()
        .unwrap_or(0)
        .max(6);
    let w2 = rows
        .iter()
        .map(|r| r.target.len())
        .max()
        .unwrap_or(0)
        .max(6);
    let mut s = format!(
        "{:<w0$} | {:<w1$} | {:<w2$} | verdict\n",
        "measurement", "figure", "target"
    );
    s += &format!(
        "{}-|-{}-|-{}-|--------\n",
        "-".repeat(w0),
        "-".repeat(w1),
        "-".repeat(w2)
    );
    for r in rows {
        s += &format!(
            "{:<w0$} | {:<w1$} | {:<w2$} | {}\n",
            r.what,
            r.figure,
            r.target,
            r.verdict.word()
        );
    }
    let fails = rows.iter().filter(|r| r.verdict == Verdict::Fail).count();
    let unmeasured = rows
        .iter()
        .filter(|r| r.verdict == Verdict::NotMeasured)
        .count();
    let passes = rows.iter().filter(|r| r.verdict == Verdict::Pass).count();
    s += &format!("targets: {passes} PASS, {fails} FAIL, {unmeasured} not measured\n");
    s
}

#[cfg(test)]
mod tests;
