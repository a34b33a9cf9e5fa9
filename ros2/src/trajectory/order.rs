//! The axis of each column of a goal's vectors: a goal may name the joints in any order.

use super::error::GoalError;
use super::joints::Joints;
use mcm_shared::NUM_AXES;

/// `axes[c]` is the axis (0-based) of column `c` of the goal's vectors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ColumnOrder {
    pub axes: [usize; NUM_AXES],
}

impl ColumnOrder {
    /// The order of `names`, which must be a permutation of the arm's joint names.
    pub fn new(names: &[String], joints: &Joints) -> Result<ColumnOrder, GoalError> {
        let mut unknown = Vec::new();
        let mut duplicate = Vec::new();
        let mut seen = [false; NUM_AXES];
        let mut axes = [0; NUM_AXES];
        for (c, name) in names.iter().enumerate() {
            match joints.axis_of(name) {
                None => unknown.push(name.clone()),
                Some(axis) if seen[axis] => {
                    if !duplicate.contains(name) {
                        duplicate.push(name.clone());
                    }
                }
                Some(axis) => {
                    seen[axis] = true;
                    if let Some(slot) = axes.get_mut(c) {
                        *slot = axis;
                    }
                }
            }
        }
        let missing: Vec<String> = (0..NUM_AXES)
            .filter(|&a| !seen[a])
            .map(|a| joints.name(a).to_string())
            .collect();
        if unknown.is_empty() && duplicate.is_empty() && missing.is_empty() {
            // Six distinct known names: exactly the six columns, each axis once.
            return Ok(ColumnOrder { axes });
        }
        Err(GoalError::JointNames {
            unknown,
            missing,
            duplicate,
            known: joints.known(),
        })
    }

    /// A goal vector (columns) in axis order. `values` has one value per column.
    pub fn axis_values(self, values: &[f64]) -> [f64; NUM_AXES] {
        let mut out = [0.0; NUM_AXES];
        for (c, v) in values.iter().enumerate().take(NUM_AXES) {
            out[self.axes[c]] = *v;
        }
        out
    }
}
