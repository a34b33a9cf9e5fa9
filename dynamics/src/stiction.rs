//! Coulomb friction with true stiction for the simulator: a velocity-level (time-stepping)
//! friction solve, the model used by Stewart–Trinkle / Anitescu-type integrators.
//!
//! Runs inside the cycle: allocation-free and panic-free.
//!
//! Over one step the velocity after the step is `v = v_free + W λ`, where `v_free` is the
//! velocity without Coulomb friction, `W = dt·A⁻¹` (A: mass matrix plus the implicit
//! spring/damper terms) and `λ` are the Coulomb torques. Each `λᵢ` lies in `[−Fᵢ, Fᵢ]` and:
//! - `vᵢ = 0` when `|λᵢ| < Fᵢ` (the joint sticks: friction supplies whatever torque holds it),
//! - `λᵢ = −Fᵢ·sign(vᵢ)` when `vᵢ ≠ 0` (the joint slides against the full Coulomb level).
//!
//! This is a box-constrained linear complementarity problem; it is solved by projected
//! Gauss-Seidel (bounded number of sweeps, deterministic), then polished: the joints found
//! sticking get their `λ` from an exact linear solve so their velocity is exactly zero, and a
//! joint at rest whose applied torque stays below its Coulomb (or brake) level does not creep
//! at all. The static level equals the Coulomb level (no Stribeck peak).
//!
//! Most steps stick and slide like the step before. So the solve first tries the previous
//! step's split (the warm start's `λ`): the exact solve of the polish for the joints that stuck,
//! kept when it satisfies every condition of the problem (the optimality conditions of the
//! box-constrained problem, whose solution is unique for a positive definite `w`). Only when it
//! does not do the Gauss-Seidel sweeps run. Both reach the same solution; the shortcut saves the
//! sweeps, which cost most of the simulator's time when the arm's coupled joints stick.

use super::mass::solve_spd;
use mcm_shared::NUM_AXES;
use nalgebra::{Matrix6, Vector6};

const N: usize = NUM_AXES;

/// Upper bound on projected Gauss-Seidel sweeps per step.
const MAX_SWEEPS: usize = 100;
/// Sweeps stop when no λ changed by more than this fraction of its bound.
const SWEEP_TOLERANCE: f64 = 1e-12;

/// Find the friction torques `lambda` (warm-started with its input) for `v = v_free + w·λ`,
/// `|λᵢ| ≤ bound[i]`. Returns the velocity after the step; sticking joints get exactly 0.
/// `w` must be symmetric positive definite; `bound[i] ≤ 0` (or not a number) means no friction
/// on joint i. A `w` with an entry that is not finite allows no solve: no friction this step
/// (`λ = 0`, the velocity is `v_free`). `λ` always comes back finite.
pub fn solve_friction(
    w: &Matrix6<f64>,
    v_free: &Vector6<f64>,
    bound: &Vector6<f64>,
    lambda: &mut Vector6<f64>,
) -> Vector6<f64> {
    if !w.iter().all(|x| x.is_finite()) {
        *lambda = Vector6::zeros();
        return *v_free;
    }
    for i in 0..N {
        let b = bound[i].max(0.0);
        let ok = lambda[i].is_finite() && w[(i, i)] > 0.0;
        lambda[i] = if ok { lambda[i].clamp(-b, b) } else { 0.0 };
    }
    if let Some(v) = keep_the_split(w, v_free, bound, lambda) {
        return v;
    }
    for _ in 0..MAX_SWEEPS {
        let mut change: f64 = 0.0;
        for i in 0..N {
            let b = bound[i];
            let d = w[(i, i)];
            if !(b > 0.0 && d > 0.0) {
                continue;
            }
            let vi = v_free[i] + w.row(i).dot(&lambda.transpose());
            let new = (lambda[i] - vi / d).clamp(-b, b);
            if new.is_finite() {
                change = change.max((new - lambda[i]).abs() / b);
                lambda[i] = new;
            }
        }
        if change <= SWEEP_TOLERANCE {
            break;
        }
    }
    let stuck = polish(w, v_free, bound, lambda);
    let mut v = v_free + w * *lambda;
    for i in 0..N {
        if stuck[i] {
            v[i] = 0.0;
        }
    }
    v
}

/// The solution when the joints stick and slide as in the warm start `lambda` (sanitised), or
/// `None` (and `lambda` untouched) when that split does not satisfy the problem's conditions:
/// a sticking joint's exact `λ` within its bound, and a sliding joint's velocity not along its
/// friction (`λᵢ = +Fᵢ` needs `vᵢ ≤ 0`, `λᵢ = −Fᵢ` needs `vᵢ ≥ 0`).
fn keep_the_split(
    w: &Matrix6<f64>,
    v_free: &Vector6<f64>,
    bound: &Vector6<f64>,
    lambda: &mut Vector6<f64>,
) -> Option<Vector6<f64>> {
    let mut trial = *lambda;
    let stuck = polish(w, v_free, bound, &mut trial);
    let mut v = v_free + w * trial;
    for i in 0..N {
        if stuck[i] {
            v[i] = 0.0;
            continue;
        }
        let b = bound[i];
        if !(b > 0.0 && w[(i, i)] > 0.0) {
            continue;
        }
        let opposes = if trial[i] == b {
            v[i] <= 0.0
        } else if trial[i] == -b {
            v[i] >= 0.0
        } else {
            false
        };
        if !opposes {
            return None;
        }
    }
    *lambda = trial;
    Some(v)
}

/// Solve exactly for the λ of the joints that stick (|λ| strictly inside its bound), the
/// others held at their bound. Keeps the Gauss-Seidel λ if the exact solution leaves a bound.
fn polish(
    w: &Matrix6<f64>,
    v_free: &Vector6<f64>,
    bound: &Vector6<f64>,
    lambda: &mut Vector6<f64>,
) -> [bool; N] {
    let mut stuck = [false; N];
    for i in 0..N {
        stuck[i] = bound[i] > 0.0 && lambda[i].abs() < bound[i] * (1.0 - 1e-9);
    }
    if !stuck.iter().any(|s| *s) {
        return stuck;
    }
    // Rows of sticking joints: Σ_{j stuck} w_ij λ_j = −v_free_i − Σ_{j sliding} w_ij λ_j.
    // Rows of sliding joints: identity (λ_j unchanged). The matrix stays SPD.
    let mut a = Matrix6::identity();
    let mut rhs = *lambda;
    for i in 0..N {
        if !stuck[i] {
            continue;
        }
        rhs[i] = -v_free[i];
        for j in 0..N {
            if stuck[j] {
                a[(i, j)] = w[(i, j)];
            } else {
                rhs[i] -= w[(i, j)] * lambda[j];
            }
        }
    }
    let exact = solve_spd(&a, &rhs);
    let inside = (0..N).all(|i| !stuck[i] || (exact[i].is_finite() && exact[i].abs() <= bound[i]));
    if inside {
        *lambda = exact;
        stuck
    } else {
        [false; N]
    }
}

#[cfg(test)]
mod tests;
