//! A flight-recorder file (`docs/safety.md`, "The flight recorder") read back: one row per
//! cycle (`cycle`, `t_s` on the robot's clock, `mode`, `command`, ...), the trip in the last
//! row. The recorder's writer thread writes the file after the trip, under a temporary name
//! that it renames to the file's name once written: [`Flight::read`] waits until it exists.

use super::WAIT;
use mcm_shared::mode::CommandKind;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// `sim` as recorded in the `command` column.
const SIM_COMMAND: u32 = CommandKind::Sim.to_wire();

/// One flight-recorder file, parsed.
pub struct Flight {
    pub path: PathBuf,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Flight {
    /// Wait until the file at `path` exists (it appears complete), then parse it and check that
    /// its last row is the trip (mode ERROR); panics after [`WAIT`].
    pub fn read(path: &Path) -> Flight {
        let deadline = Instant::now() + WAIT;
        while !path.exists() {
            assert!(
                Instant::now() < deadline,
                "{} not written within {WAIT:?}",
                path.display()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        let text = std::fs::read_to_string(path)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        let mut lines = text.lines();
        let header = lines
            .next()
            .unwrap()
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect();
        let f = Flight {
            path: path.to_path_buf(),
            header,
            rows,
        };
        assert_eq!(
            f.text(f.last(), "mode"),
            "ERROR",
            "the last row of {} is the trip",
            path.display()
        );
        f
    }

    pub fn col(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {}", self.path.display()))
    }

    pub fn text(&self, row: usize, name: &str) -> &str {
        &self.rows[row][self.col(name)]
    }

    pub fn num(&self, row: usize, name: &str) -> f64 {
        let s = self.text(row, name);
        s.parse()
            .unwrap_or_else(|_| panic!("{name} = {s:?} in row {row} is not a number"))
    }

    pub fn column(&self, name: &str) -> Vec<f64> {
        (0..self.rows.len()).map(|r| self.num(r, name)).collect()
    }

    /// The row of the trip (the last one).
    pub fn last(&self) -> usize {
        self.rows.len() - 1
    }

    /// The last row before the trip where a `sim` command was served.
    pub fn last_sim_before_trip(&self) -> usize {
        (0..self.last())
            .rev()
            .find(|&r| self.num(r, "command") as u32 == SIM_COMMAND)
            .unwrap_or_else(|| panic!("no sim command in {}", self.path.display()))
    }
}
