//! Inverse kinematics: every joint configuration that puts the TCP at a pose.
//!
//! Closed form for the arms of [`crate::shape`]: the wrist centre (where axes 4, 5 and 6 meet)
//! follows from the flange pose; axis 1 turns the plane of axes 2 and 3 through it (two ways:
//! the wrist centre in front of axis 1 or behind it), axes 2 and 3 reach it as a planar
//! two-link arm (elbow on one side of the line from axis 2 to the wrist centre or the other),
//! and axes 4, 5 and 6 turn the flange into the asked orientation (two ways: θ5 positive or
//! negative). Up to 2 × 2 × 2 = 8 solutions.
//!
//! Each joint angle is moved by whole turns into its axis's reachable range, the value nearest
//! the seed's for that axis (an axis with more than a turn of range could take another; that
//! one is farther from the seed and not returned). A solution with an axis outside its range
//! is dropped; solutions that coincide (at a singularity) are returned once. The rest are
//! sorted by [`travel_time`] from the seed, nearest first.
//!
//! At a singularity where a joint is free (the wrist centre on axis 1 with no shoulder
//! offset: axis 1; axes 4 and 6 aligned: axis 4) that joint keeps the seed's value (and the
//! other branch its value plus half a turn); the remaining joints are solved for it, so the
//! pose is still met exactly.

use crate::limits::{AxisRange, Miss, travel_time};
use crate::{Kinematics, N};
use mcm_shared::ranges::Num;
use nalgebra::{Isometry3, Matrix3, Vector3};
use std::f64::consts::{PI, TAU};

/// The most solutions a pose has: shoulder, elbow and wrist each on one of two sides.
pub const MAX_SOLUTIONS: usize = 8;

/// A distance under which a free joint is taken as free (the wrist centre on axis 1 or axis
/// 2, axes 4 and 6 aligned) [m, or the sine of an angle]: the joint keeps the seed's value.
const FREE_JOINT: f64 = 1e-12;

/// How far beyond the arm's reach (or inside its shoulder offset) the wrist centre may be
/// and still count as reached [m]: it is then taken as on the boundary.
pub const REACH_TOLERANCE_M: f64 = 1e-9;

/// Two solutions closer than this on every axis are one [rad].
const SAME_RAD: f64 = 1e-9;

/// One side of a two-way choice of the solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    Positive,
    Negative,
}

impl Side {
    fn sign(self) -> f64 {
        match self {
            Side::Positive => 1.0,
            Side::Negative => -1.0,
        }
    }
}

/// Which of the (up to) eight solutions a configuration is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Branch {
    /// `Positive`: the wrist centre in front of axis 1 (along x of DH frame 1 turned back by
    /// its twist: the arm reaches forward); `Negative`: behind it (over the back).
    pub shoulder: Side,
    /// The sign of the sine of the angle from the upper arm (axis 2 to axis 3) to the forearm
    /// (axis 3 to the wrist centre), about axis 3. For the P-Rob2 reaching forward,
    /// `Negative` is the elbow up.
    pub elbow: Side,
    /// The sign of sin θ5 (θ5 = q5 + offset5).
    pub wrist: Side,
}

/// A solution: joint values [rad] within the axes' reachable ranges, and its branch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solution {
    pub q: [f64; N],
    pub branch: Branch,
}

/// The solutions of one call, nearest the seed first; inline, no heap.
pub type Solutions = heapless::Vec<Solution, MAX_SOLUTIONS>;

/// Why inverse kinematics found no solution. Lengths in metres, angles in degrees.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IkError {
    /// The target pose or the seed is not made of finite numbers.
    #[error("the {what} has {value}; it needs finite numbers")]
    NotFinite { what: &'static str, value: f64 },
    /// The wrist centre lies beyond the arm's reach, or too near axis 2 for the folded arm.
    #[error(
        "unreachable: the wrist centre would be {} m from axis 2; the arm reaches it from {} \
         to {} m",
        Num(*.distance_m),
        Num(*.min_m),
        Num(*.max_m)
    )]
    OutOfReach {
        distance_m: f64,
        min_m: f64,
        max_m: f64,
    },
    /// The wrist centre lies nearer to axis 1 than the arm's lateral (shoulder) offset.
    #[error(
        "unreachable: the wrist centre would be {} m from axis 1; the arm's shoulder offset \
         keeps it at least {} m away",
        Num(*.distance_m),
        Num(*.offset_m)
    )]
    InsideShoulderOffset { distance_m: f64, offset_m: f64 },
    /// Every solution has an axis outside its reachable range; the nearest miss is named.
    #[error(
        "unreachable within the axis limits: all {found} solutions put an axis outside its \
         reachable range; the nearest puts axis {axis} at {} deg, outside {} to {} deg",
        Num(*.value_deg),
        Num(*.min_deg),
        Num(*.max_deg)
    )]
    OutsideLimits {
        found: usize,
        /// 1-based.
        axis: usize,
        value_deg: f64,
        min_deg: f64,
        max_deg: f64,
    },
}

fn finite(what: &'static str, values: &[f64]) -> Result<(), IkError> {
    match values.iter().find(|v| !v.is_finite()) {
        None => Ok(()),
        Some(&value) => Err(IkError::NotFinite { what, value }),
    }
}

/// What the solution needs of a flange pose, and the seed as joint angles θ.
struct Target {
    centre: Vector3<f64>,
    axis6: Vector3<f64>,
    r6: Matrix3<f64>,
    theta_seed: [f64; N],
}

/// The solutions found so far, and the nearest miss of those dropped.
struct Found {
    solutions: Solutions,
    candidates: usize,
    nearest_miss: Option<Miss>,
}

impl Kinematics {
    /// Every joint configuration within the axes' reachable ranges that puts the TCP at
    /// `target` (base frame), the nearest to `seed` [rad] first ([`travel_time`]).
    ///
    /// Allocation-free and panic-free: usable in the cycle.
    pub fn inverse(&self, target: &Isometry3<f64>, seed: &[f64; N]) -> Result<Solutions, IkError> {
        self.inverse_flange(&(target * self.tcp_inverse), seed)
    }

    /// [`Kinematics::inverse`] for a pose of the flange instead of the TCP.
    pub fn inverse_flange(
        &self,
        flange: &Isometry3<f64>,
        seed: &[f64; N],
    ) -> Result<Solutions, IkError> {
        let t = self.wrist_target(flange, seed)?;
        let mut found = Found {
            solutions: Solutions::new(),
            candidates: 0,
            nearest_miss: None,
        };
        let mut reach_error = None;
        for shoulder in [Side::Positive, Side::Negative] {
            for elbow in [Side::Positive, Side::Negative] {
                let arm = match self.arm_angles(&t, shoulder, elbow) {
                    Ok(arm) => arm,
                    Err(e) => {
                        reach_error.get_or_insert(e);
                        continue;
                    }
                };
                let r3 = self.rotation3(&arm);
                for wrist in [Side::Positive, Side::Negative] {
                    let theta = self.wrist_angles(arm, &r3, &t, wrist);
                    found.candidates += 1;
                    let branch = Branch {
                        shoulder,
                        elbow,
                        wrist,
                    };
                    match self.fit(&theta, seed) {
                        Ok(q) => {
                            let same = |s: &Solution| {
                                s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < SAME_RAD)
                            };
                            if !found.solutions.iter().any(same) {
                                // At most 8 candidates: the storage never overflows.
                                let _ = found.solutions.push(Solution { q, branch });
                            }
                        }
                        Err(miss) => {
                            if found.nearest_miss.is_none_or(|m| miss.by < m.by) {
                                found.nearest_miss = Some(miss);
                            }
                        }
                    }
                }
            }
        }
        if let (0, Some(e)) = (found.candidates, reach_error) {
            return Err(e);
        }
        if found.solutions.is_empty() {
            let m = found.nearest_miss.unwrap_or(Miss {
                axis: 0,
                value: f64::NAN,
                by: f64::NAN,
            });
            let range = self.ranges[m.axis];
            return Err(IkError::OutsideLimits {
                found: found.candidates,
                axis: m.axis + 1,
                value_deg: m.value.to_degrees(),
                min_deg: range.min.to_degrees(),
                max_deg: range.max.to_degrees(),
            });
        }
        sort_by_travel(&mut found.solutions, seed, &self.speed);
        Ok(found.solutions)
    }

    /// The one solution of `branch` that puts the TCP at `target`, each joint value moved by
    /// whole turns nearest the seed's and **not** checked against the axes' ranges (the caller
    /// decides what a value outside them means). What a path of poses follows continuously:
    /// away from singularities the solution of a branch changes smoothly with the pose.
    /// Allocation-free and panic-free.
    pub fn inverse_branch(
        &self,
        target: &Isometry3<f64>,
        branch: Branch,
        seed: &[f64; N],
    ) -> Result<[f64; N], IkError> {
        let t = self.wrist_target(&(target * self.tcp_inverse), seed)?;
        let arm = self.arm_angles(&t, branch.shoulder, branch.elbow)?;
        let theta = self.wrist_angles(arm, &self.rotation3(&arm), &t, branch.wrist);
        Ok(core::array::from_fn(|i| {
            let v = theta[i] - self.links[i].offset;
            v + TAU * ((seed[i] - v) / TAU).round()
        }))
    }

    /// Which branch the configuration `q` [rad] is on: the [`Branch`] the inverse kinematics
    /// gives it. At a singularity (a side's measure exactly 0) that side is `Positive`.
    pub fn branch(&self, q: &[f64; N]) -> Branch {
        let sh = &self.shape;
        let f = self.frames(q);
        let c = f.origin[3];
        let th1 = q[0] + self.links[0].offset;
        // The wrist centre along x of the arm's plane (`u` of the solution, signed).
        let us = th1.cos() * c.x + th1.sin() * c.y;
        let phi = q[2] + self.links[2].offset + sh.forearm_angle;
        let th5 = q[4] + self.links[4].offset;
        let side = |v: f64| {
            if v < 0.0 {
                Side::Negative
            } else {
                Side::Positive
            }
        };
        Branch {
            shoulder: side(us),
            elbow: side(phi.sin()),
            wrist: side(th5.sin()),
        }
    }

    /// The wrist centre, axis 6's direction and the flange's rotation for a flange pose.
    fn wrist_target(&self, flange: &Isometry3<f64>, seed: &[f64; N]) -> Result<Target, IkError> {
        let p6 = flange.translation.vector;
        finite("target position", p6.as_slice())?;
        finite("target orientation", flange.rotation.coords.as_slice())?;
        finite("seed", seed)?;
        let sh = &self.shape;
        let r6 = flange.rotation.to_rotation_matrix().into_inner();
        let centre = p6 - r6 * sh.wrist_offset;
        // Axis 1: the wrist centre at distance `lateral` beside the arm's plane.
        let r = centre.x.hypot(centre.y);
        if r < sh.lateral.abs() - REACH_TOLERANCE_M {
            return Err(IkError::InsideShoulderOffset {
                distance_m: r,
                offset_m: sh.lateral.abs(),
            });
        }
        Ok(Target {
            centre,
            axis6: r6 * sh.axis6,
            r6,
            theta_seed: core::array::from_fn(|i| seed[i] + self.links[i].offset),
        })
    }

    /// θ1, θ2, θ3 of one shoulder and elbow branch, or why the wrist centre is out of reach.
    fn arm_angles(&self, t: &Target, shoulder: Side, elbow: Side) -> Result<[f64; 3], IkError> {
        let sh = &self.shape;
        let c = t.centre;
        let r = c.x.hypot(c.y);
        let e = sh.lateral;
        let us = shoulder.sign() * (r * r - e * e).max(0.0).sqrt();
        let th1 = if r < FREE_JOINT {
            t.theta_seed[0] + if shoulder == Side::Negative { PI } else { 0.0 }
        } else {
            c.y.atan2(c.x) - e.atan2(us)
        };
        // The wrist centre in the plane of axes 2 and 3 (frame 1's x-y).
        let x = us - sh.a1;
        let y = sh.s1 * (c.z - sh.d1);
        let dist = x.hypot(y);
        let (a2, l) = (sh.a2, sh.forearm);
        let (min, max) = ((a2.abs() - l).abs(), a2.abs() + l);
        if dist > max + REACH_TOLERANCE_M || dist < min - REACH_TOLERANCE_M {
            return Err(IkError::OutOfReach {
                distance_m: dist,
                min_m: min,
                max_m: max,
            });
        }
        let cos = ((dist * dist - a2 * a2 - l * l) / (2.0 * a2 * l)).clamp(-1.0, 1.0);
        let phi = elbow.sign() * cos.acos();
        let th2 = if dist < FREE_JOINT {
            t.theta_seed[1]
        } else {
            y.atan2(x) - (l * phi.sin()).atan2(a2 + l * phi.cos())
        };
        Ok([th1, th2, phi - sh.forearm_angle])
    }

    /// Frame 3's rotation for θ1, θ2, θ3.
    fn rotation3(&self, arm: &[f64; 3]) -> Matrix3<f64> {
        self.links[0].rotation_at_theta(arm[0])
            * self.links[1].rotation_at_theta(arm[1])
            * self.links[2].rotation_at_theta(arm[2])
    }

    /// All six angles θ for the arm's angles `arm` (frame 3's rotation `r3`) and one wrist
    /// branch.
    fn wrist_angles(&self, arm: [f64; 3], r3: &Matrix3<f64>, t: &Target, wrist: Side) -> [f64; N] {
        let sh = &self.shape;
        // Axis 6 seen from frame 3 is Rz(θ4) (s5 sin θ5, 0, ·): θ4 points along it.
        let w = r3.transpose() * t.axis6;
        let th4_base = if w.x.hypot(w.y) < FREE_JOINT {
            t.theta_seed[3]
        } else {
            (sh.s5 * w.y).atan2(sh.s5 * w.x)
        };
        let th4 = th4_base + if wrist == Side::Negative { PI } else { 0.0 };
        let r4 = r3 * self.links[3].rotation_at_theta(th4);
        // Axis 6 seen from frame 4: Rz(θ5) Rx(α5) z = (s5 sin θ5, −s5 cos θ5, ·).
        let v = r4.transpose() * t.axis6;
        let th5 = (sh.s5 * v.x).atan2(-sh.s5 * v.y);
        let r5 = r4 * self.links[4].rotation_at_theta(th5);
        // Rz(θ6) = R5ᵀ R6 Rx(α6)ᵀ.
        let n = r5.transpose() * t.r6 * sh.unturn6;
        let th6 = n[(1, 0)].atan2(n[(0, 0)]);
        [arm[0], arm[1], arm[2], th4, th5, th6]
    }

    /// Joint values from the angles θ: the offsets taken off, each moved into its range nearest
    /// the seed; the first axis that misses otherwise.
    fn fit(&self, theta: &[f64; N], seed: &[f64; N]) -> Result<[f64; N], Miss> {
        let mut q = [0.0; N];
        let mut worst: Option<Miss> = None;
        for (i, (range, link)) in self.ranges.iter().zip(&self.links).enumerate() {
            match AxisRange::fit(range, i, theta[i] - link.offset, seed[i]) {
                Ok(v) => q[i] = v,
                Err(m) => {
                    if worst.is_none_or(|w| m.by > w.by) {
                        worst = Some(m);
                    }
                }
            }
        }
        match worst {
            None => Ok(q),
            Some(m) => Err(m),
        }
    }
}

/// Insertion sort (at most 8 elements, no allocation) by [`travel_time`] from `seed`.
fn sort_by_travel(solutions: &mut Solutions, seed: &[f64; N], speed: &[f64; N]) {
    let key = |s: &Solution| travel_time(seed, &s.q, speed);
    for i in 1..solutions.len() {
        let mut j = i;
        while j > 0 && key(&solutions[j]) < key(&solutions[j - 1]) {
            solutions.swap(j, j - 1);
            j -= 1;
        }
    }
}

#[cfg(test)]
mod tests;
