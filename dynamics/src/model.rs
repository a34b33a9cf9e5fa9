//! The arm model: standard-DH kinematics and the inertial data of the six links plus the tool,
//! built once from the configuration (`[arm]` and the per-axis armature and friction).
//!
//! Runs inside the cycle: everything except [`ArmModel::from_config`] /
//! [`ArmModel::try_from_config`] is allocation-free and panic-free (fixed-size nalgebra types).
//!
//! The tool (gripper + payload, `[arm.tool]` at start) is a body fixed to frame 6: a mass at
//! its centre of mass, with its own inertia (zero for a point mass). It is lumped into link 6
//! (combined mass, centre of mass and inertia by the parallel-axis theorem), so the dynamics
//! see six rigid bodies. [`ArmModel::set_tool`] changes it at run time.
//!
//! ```
//! use mcm_dynamics::ArmModel;
//! let model = ArmModel::from_config(&mcm_shared::config::RobotConfig::prob2_default());
//! let flange = model.flange_pose(&[0.0; 6]);
//! assert!((flange.translation.z - 1.035).abs() < 1e-12); // upright zero pose
//! ```

use super::DynamicsError;
use super::friction::JointFriction;
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;
use mcm_shared::tool::Tool;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3, Vector6};

const N: usize = NUM_AXES;

/// One link as configured: standard DH parameters and inertial data (without the tool).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Link {
    /// DH offset along z_{i-1} [m].
    pub d: f64,
    /// DH length along x_i [m].
    pub a: f64,
    /// DH twist about x_i [rad].
    pub alpha: f64,
    /// Joint offset: θ = q + offset [rad].
    pub offset: f64,
    /// Mass [kg].
    pub mass: f64,
    /// Centre of mass in the link's DH frame [m].
    pub com: Vector3<f64>,
    /// Inertia about the centre of mass, axes of the link frame [kg m²].
    pub inertia: Matrix3<f64>,
}

impl Link {
    /// Rotation and origin of frame i expressed in frame i−1 for joint angle `q`.
    pub fn local_transform(&self, q: f64) -> (Matrix3<f64>, Vector3<f64>) {
        self.local_transform_twisted(q, self.alpha.sin_cos())
    }

    /// [`Link::local_transform`] with the sine and cosine of the twist already known (the
    /// model keeps them: the kinematics run several times a cycle in the simulation).
    fn local_transform_twisted(
        &self,
        q: f64,
        (sa, ca): (f64, f64),
    ) -> (Matrix3<f64>, Vector3<f64>) {
        let (st, ct) = (q + self.offset).sin_cos();
        #[rustfmt::skip]
        let r = Matrix3::new(
            ct, -st * ca,  st * sa,
            st,  ct * ca, -ct * sa,
            0.0,      sa,       ca,
        );
        (r, Vector3::new(self.a * ct, self.a * st, self.d))
    }
}

/// Mass, centre of mass and inertia of one rigid body as used by the dynamics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Inertial {
    pub mass: f64,
    /// In the link frame [m].
    pub com: Vector3<f64>,
    /// About the centre of mass, link-frame axes [kg m²].
    pub inertia: Matrix3<f64>,
}

/// Positions, axes and world inertias of all links for one joint vector. Internal.
#[derive(Debug, Clone, Copy)]
pub(super) struct Kinematics {
    /// World direction of joint i's axis (z of frame i−1).
    pub axis: [Vector3<f64>; N],
    /// World position of a point on joint i's axis (origin of frame i−1).
    pub joint_origin: [Vector3<f64>; N],
    /// World rotation of frame i.
    pub rot: [Matrix3<f64>; N],
    /// World origin of frame i.
    pub origin: [Vector3<f64>; N],
    /// World centre of mass of body i.
    pub com: [Vector3<f64>; N],
    /// World inertia of body i about its centre of mass.
    pub inertia: [Matrix3<f64>; N],
}

/// The rigid-body model of the arm. Cheap to clone (plain data, no heap).
#[derive(Debug, Clone, PartialEq)]
pub struct ArmModel {
    links: [Link; N],
    /// Sine and cosine of each link's twist `alpha`.
    twist: [(f64, f64); N],
    /// The tool lumped into body 6.
    tool: Tool,
    /// Bodies used by the dynamics: links 1..5 as configured, link 6 with the tool lumped in.
    pub(super) bodies: [Inertial; N],
    pub(super) gravity: Vector3<f64>,
    pub(super) armature: [f64; N],
    pub(super) friction: [JointFriction; N],
}

fn check(
    key: impl FnOnce() -> String,
    value: f64,
    ok: bool,
    allowed: &'static str,
) -> Result<(), DynamicsError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(DynamicsError::Invalid {
            key: key(),
            value,
            allowed,
        })
    }
}

impl ArmModel {
    /// Build the model from a validated configuration.
    ///
    /// # Panics
    /// Only for a configuration that `RobotConfig::validate` would refuse (wrong number of
    /// links or axes, non-finite or non-positive masses...). Use [`ArmModel::try_from_config`]
    /// to get the error instead. Start-up only; never called in the cycle.
    pub fn from_config(cfg: &RobotConfig) -> ArmModel {
        match Self::try_from_config(cfg) {
            Ok(m) => m,
            Err(e) => panic!("arm model from an invalid configuration: {e}"),
        }
    }

    /// Build the model, refusing out-of-range parameters with a typed error naming the key.
    pub fn try_from_config(cfg: &RobotConfig) -> Result<ArmModel, DynamicsError> {
        let arm = &cfg.arm;
        if arm.links.len() != N {
            return Err(DynamicsError::WrongCount {
                key: "arm.link",
                found: arm.links.len(),
            });
        }
        if cfg.axes.len() != N {
            return Err(DynamicsError::WrongCount {
                key: "axis",
                found: cfg.axes.len(),
            });
        }
        let mut links = [Link {
            d: 0.0,
            a: 0.0,
            alpha: 0.0,
            offset: 0.0,
            mass: 0.0,
            com: Vector3::zeros(),
            inertia: Matrix3::zeros(),
        }; N];
        for (i, (l, out)) in arm.links.iter().zip(links.iter_mut()).enumerate() {
            let k = |name: &str| format!("arm.link[{}].{name}", i + 1);
            for (name, v) in [
                ("d", l.d),
                ("a", l.a),
                ("alpha_deg", l.alpha_deg),
                ("offset_deg", l.offset_deg),
            ] {
                check(|| k(name), v, true, "a finite value")?;
            }
            check(|| k("mass"), l.mass, l.mass > 0.0, "a finite mass > 0 kg")?;
            for v in l.com {
                check(|| k("com"), v, true, "finite coordinates [m]")?;
            }
            for v in l.inertia {
                check(
                    || k("inertia"),
                    v,
                    v > 0.0,
                    "finite principal inertias > 0 kg m^2",
                )?;
            }
            *out = Link {
                d: l.d,
                a: l.a,
                alpha: l.alpha_deg.to_radians(),
                offset: l.offset_deg.to_radians(),
                mass: l.mass,
                com: Vector3::from(l.com),
                inertia: Matrix3::from_diagonal(&Vector3::from(l.inertia)),
            };
        }
        let tool = arm.tool.tool().map_err(|e| DynamicsError::Invalid {
            key: format!("arm.tool.{}", e.field()),
            value: e.value(),
            allowed: e.allowed(),
        })?;
        for v in arm.gravity {
            check(
                || "arm.gravity".into(),
                v,
                true,
                "finite components [m/s^2]",
            )?;
        }
        let mut armature = [0.0; N];
        let mut friction = [JointFriction::default(); N];
        for (i, a) in cfg.axes.iter().enumerate() {
            let k = |name: &str| format!("axis[{}].{name}", i + 1);
            check(
                || k("armature_kg_m2"),
                a.armature_kg_m2,
                a.armature_kg_m2 >= 0.0,
                "a finite value >= 0",
            )?;
            let (fc, fv) = (a.coulomb_friction_nm, a.viscous_friction_nm_s_rad);
            check(
                || k("coulomb_friction_nm"),
                fc,
                fc >= 0.0,
                "a finite value >= 0",
            )?;
            check(
                || k("viscous_friction_nm_s_rad"),
                fv,
                fv >= 0.0,
                "a finite value >= 0",
            )?;
            armature[i] = a.armature_kg_m2;
            friction[i] = JointFriction {
                coulomb: fc,
                viscous: fv,
            };
        }
        let mut model = ArmModel {
            links,
            twist: links.map(|l| l.alpha.sin_cos()),
            tool: Tool::NONE,
            bodies: [Inertial {
                mass: 0.0,
                com: Vector3::zeros(),
                inertia: Matrix3::zeros(),
            }; N],
            gravity: Vector3::from(arm.gravity),
            armature,
            friction,
        };
        for (b, l) in model.bodies.iter_mut().zip(&links) {
            *b = Inertial {
                mass: l.mass,
                com: l.com,
                inertia: l.inertia,
            };
        }
        model.set_tool(&tool);
        Ok(model)
    }

    /// Replace the tool (gripper + payload): its mass at its centre of mass in frame 6, with
    /// its inertia about that point (a [`Tool`] is checked when it is made: finite, mass ≥ 0,
    /// a physical inertia). Its TCP does not enter the dynamics. Allocation-free; may be
    /// called in the cycle.
    pub fn set_tool(&mut self, tool: &Tool) {
        self.tool = *tool;
        let com = Vector3::from(tool.center_of_mass);
        let [ixx, iyy, izz, ixy, ixz, iyz] = tool.inertia;
        #[rustfmt::skip]
        let inertia = Matrix3::new(
            ixx, ixy, ixz,
            ixy, iyy, iyz,
            ixz, iyz, izz,
        );
        let l = &self.links[N - 1];
        let m = l.mass + tool.mass;
        let c = (l.com * l.mass + com * tool.mass) / m;
        // Parallel-axis theorem: inertia of a point mass at offset r is m (|r|² I − r rᵀ).
        let shift = |mass: f64, r: Vector3<f64>| {
            (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * mass
        };
        self.bodies[N - 1] = Inertial {
            mass: m,
            com: c,
            inertia: l.inertia + shift(l.mass, l.com - c) + inertia + shift(tool.mass, com - c),
        };
    }

    /// The tool lumped into body 6.
    pub fn tool(&self) -> &Tool {
        &self.tool
    }

    /// Link `i` (0-based) as configured, `None` for i ≥ 6.
    pub fn link(&self, i: usize) -> Option<&Link> {
        self.links.get(i)
    }

    /// Gravity vector in the base frame [m/s²].
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    /// Armature (reflected motor inertia) per axis [kg m²].
    pub fn armature(&self) -> [f64; N] {
        self.armature
    }

    /// Friction parameters per axis.
    pub fn friction(&self) -> [JointFriction; N] {
        self.friction
    }

    /// Total moving mass including the tool [kg].
    pub fn total_mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.mass).sum()
    }

    pub(super) fn kinematics(&self, q: &[f64; N]) -> Kinematics {
        let mut k = Kinematics {
            axis: [Vector3::zeros(); N],
            joint_origin: [Vector3::zeros(); N],
            rot: [Matrix3::identity(); N],
            origin: [Vector3::zeros(); N],
            com: [Vector3::zeros(); N],
            inertia: [Matrix3::zeros(); N],
        };
        let mut r = Matrix3::identity();
        let mut o = Vector3::zeros();
        for (i, qi) in q.iter().enumerate() {
            k.axis[i] = r.column(2).into_owned();
            k.joint_origin[i] = o;
            let (rl, ol) = self.links[i].local_transform_twisted(*qi, self.twist[i]);
            o += r * ol;
            r *= rl;
            let b = &self.bodies[i];
            k.rot[i] = r;
            k.origin[i] = o;
            k.com[i] = o + r * b.com;
            k.inertia[i] = r * b.inertia * r.transpose();
        }
        k
    }

    /// Poses of DH frames 1..6 in the base frame.
    pub fn link_frames(&self, q: &[f64; N]) -> [Isometry3<f64>; N] {
        let k = self.kinematics(q);
        let mut out = [Isometry3::identity(); N];
        for (f, (r, o)) in out.iter_mut().zip(k.rot.iter().zip(&k.origin)) {
            *f = iso(r, o);
        }
        out
    }

    /// Forward kinematics: pose of the flange (DH frame 6) in the base frame.
    pub fn flange_pose(&self, q: &[f64; N]) -> Isometry3<f64> {
        let mut r = Matrix3::identity();
        let mut o = Vector3::zeros();
        for ((l, twist), qi) in self.links.iter().zip(&self.twist).zip(q) {
            let (rl, ol) = l.local_transform_twisted(*qi, *twist);
            o += r * ol;
            r *= rl;
        }
        iso(&r, &o)
    }

    /// World positions of the six bodies' centres of mass (body 6 includes the tool) [m].
    pub fn com_positions(&self, q: &[f64; N]) -> [Vector3<f64>; N] {
        self.kinematics(q).com
    }

    /// Masses of the six bodies as used by the dynamics (body 6 includes the tool) [kg].
    pub fn body_masses(&self) -> [f64; N] {
        let mut m = [0.0; N];
        for (m, b) in m.iter_mut().zip(&self.bodies) {
            *m = b.mass;
        }
        m
    }

    /// Potential energy in the gravity field, zero at the base origin [J].
    pub fn potential_energy(&self, q: &[f64; N]) -> f64 {
        let k = self.kinematics(q);
        self.bodies
            .iter()
            .zip(&k.com)
            .map(|(b, c)| -b.mass * self.gravity.dot(c))
            .sum()
    }

    /// Kinetic energy of the links and of the rotors (armature) [J]. Computed from the link
    /// velocities directly, independently of the mass matrix (the tests compare the two).
    pub fn kinetic_energy(&self, q: &[f64; N], qd: &[f64; N]) -> f64 {
        let k = self.kinematics(q);
        let mut w = Vector3::zeros();
        let mut v = Vector3::zeros(); // velocity of the origin of the previous frame
        let mut e = 0.0;
        for (i, &v_i) in qd.iter().enumerate() {
            // The origin of frame i−1 lies on joint i's axis: its velocity is the same on both
            // sides of the joint.
            w += k.axis[i] * v_i;
            let b = &self.bodies[i];
            let vc = v + w.cross(&(k.com[i] - k.joint_origin[i]));
            e += 0.5 * b.mass * vc.norm_squared() + 0.5 * w.dot(&(k.inertia[i] * w));
            e += 0.5 * self.armature[i] * v_i * v_i;
            v += w.cross(&(k.origin[i] - k.joint_origin[i]));
        }
        e
    }

    /// Geometric Jacobian of the flange (rows: linear velocity, angular velocity in the base
    /// frame; columns: joints).
    pub fn flange_jacobian(&self, q: &[f64; N]) -> nalgebra::Matrix6<f64> {
        let k = self.kinematics(q);
        let p = k.origin[N - 1];
        let mut j = nalgebra::Matrix6::zeros();
        for i in 0..N {
            let lin = k.axis[i].cross(&(p - k.joint_origin[i]));
            let col = Vector6::new(lin.x, lin.y, lin.z, k.axis[i].x, k.axis[i].y, k.axis[i].z);
            j.set_column(i, &col);
        }
        j
    }
}

fn iso(r: &Matrix3<f64>, o: &Vector3<f64>) -> Isometry3<f64> {
    let rot = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*r));
    Isometry3::from_parts(Translation3::from(*o), rot)
}

#[cfg(test)]
mod tests;
