//! The true TCP watched while an example draws a square in the air with `move_linear`
//! (`examples/{python,rust,cpp}/draw_square.*`): a thread polls the simulation's ground truth
//! (`sim` `true_position`, through the forward kinematics of the P-Rob2 and its configured
//! tool) for as long as the example runs, and [`assert_square`] checks the path it saw against
//! the square the example says it started from.

use super::tcp::{kinematics, minus, norm, true_tcp};
use super::{Client, Mcm};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

/// How far the true TCP may leave the square's sides, above or below its plane or outside its
/// outline [m]: `move_linear`'s own target is 1 mm of its line (`tests/end_to_end/move_linear.rs`).
pub const OFF_SQUARE_M: f64 = 0.001;
/// How near the true TCP must come to each corner [m] (it rests there between two sides).
pub const AT_CORNER_M: f64 = 0.0005;

/// The true TCP positions [m] seen while something runs.
pub struct TcpWatch {
    stop: Arc<AtomicBool>,
    thread: JoinHandle<Vec<[f64; 3]>>,
}

impl TcpWatch {
    /// Start polling the true TCP of `mcm` (every 5 ms of the wall clock; the checks below
    /// are on positions, not times).
    pub fn start(mcm: &Mcm) -> TcpWatch {
        let stop = Arc::new(AtomicBool::new(false));
        let mut c: Client = mcm.client();
        let kin = kinematics();
        let until = stop.clone();
        let thread = std::thread::spawn(move || {
            let mut seen = Vec::new();
            while !until.load(Ordering::Relaxed) {
                let (q, v) = c.truth();
                seen.push(true_tcp(&kin, &q, &v).position);
                std::thread::sleep(Duration::from_millis(5));
            }
            seen
        });
        TcpWatch { stop, thread }
    }

    /// Stop polling; every position seen.
    pub fn finish(self) -> Vec<[f64; 3]> {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.join().expect("the watching thread")
    }
}

/// Check `seen` (the true TCP while the example ran) against the horizontal square of `side`
/// [m] whose first corner the example printed (`start corner [m]: x y z` in `out`): once the
/// TCP is at that corner, it stays within [`OFF_SQUARE_M`] of the square's plane and outline,
/// comes within [`AT_CORNER_M`] of every corner, and ends at the first. Returns how far it
/// strayed at most [m].
pub fn assert_square(out: &str, seen: &[[f64; 3]], side: f64) -> f64 {
    const MARK: &str = "start corner [m]:";
    let at = out
        .find(MARK)
        .unwrap_or_else(|| panic!("no {MARK:?} in the output: {out}"));
    let xyz: Vec<f64> = out[at + MARK.len()..]
        .split_whitespace()
        .take(3)
        .map(|w| {
            w.parse()
                .unwrap_or_else(|e| panic!("{w:?} after {MARK:?}: {e}"))
        })
        .collect();
    let [x, y, z] = xyz[..] else {
        panic!("three numbers after {MARK:?}: {out}")
    };
    let corners = [
        [x, y, z],
        [x + side, y, z],
        [x + side, y + side, z],
        [x, y + side, z],
    ];
    let dist = |a: &[f64; 3], b: &[f64; 3]| norm(&minus(a, b));
    // The first corner is reached by a joint move before the example prints it: from then on.
    let from = seen
        .iter()
        .position(|p| dist(p, &corners[0]) < AT_CORNER_M)
        .unwrap_or_else(|| panic!("the true TCP never at the start corner {:?}", corners[0]));
    let path = &seen[from..];
    let mut worst = 0.0f64;
    for p in path {
        // Outside the outline: beyond the square in x or y; off the sides: inside, far from
        // every side; off the plane: in z.
        let out_x = (x - p[0]).max(p[0] - (x + side)).max(0.0);
        let out_y = (y - p[1]).max(p[1] - (y + side)).max(0.0);
        let to_side = [p[0] - x, x + side - p[0], p[1] - y, y + side - p[1]]
            .into_iter()
            .fold(f64::INFINITY, |m, d| m.min(d.abs()));
        let stray = (p[2] - z)
            .abs()
            .max(out_x.max(out_y))
            .max(if out_x + out_y > 0.0 { 0.0 } else { to_side });
        worst = worst.max(stray);
    }
    assert!(
        worst < OFF_SQUARE_M,
        "the true TCP left the square by {worst} m (allowed {OFF_SQUARE_M})"
    );
    for c in &corners {
        let nearest = path
            .iter()
            .map(|p| dist(p, c))
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < AT_CORNER_M,
            "the true TCP came only {nearest} m near the corner {c:?}"
        );
    }
    let last = path.last().expect("a position after the start");
    assert!(
        dist(last, &corners[0]) < AT_CORNER_M,
        "the true TCP ended at {last:?}, not back at {:?}",
        corners[0]
    );
    worst
}
