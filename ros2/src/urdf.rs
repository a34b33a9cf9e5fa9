//! The robot description (URDF) published on `/robot_description`, generated from the robot
//! configuration (`[[axis]]` and `[arm]`), the same data the controller and `mcm-dynamics` use:
//! RViz, MoveIt and robot_state_publisher see the kinematics the MCM moves by.
//!
//! # Frames
//! - `{prefix}base_link`: DH frame 0, the base frame of the MCM's Cartesian poses.
//! - `{prefix}link_i` (i = 1..6): the body of DH link i, in the frame of joint i: DH frame i−1
//!   turned by the joint angle about its z axis. (URDF turns a joint's child after the joint's
//!   fixed origin; standard DH turns by θ = q + offset first: frame i = frame i−1 · Rz(q) ·
//!   Rz(offset) Tz(d) Tx(a) Rx(alpha).) The fixed part Rz(offset) Tz(d) Tx(a) Rx(alpha) of link i
//!   is the origin of the next joint in `link_i`: xyz = (a cos offset, a sin offset, d),
//!   rpy = (alpha, 0, offset) (URDF's rpy is R = Rz(yaw) Ry(pitch) Rx(roll)).
//! - `{prefix}flange`: DH frame 6, the MCM's flange (`ArmModel::flange_pose`, the frame of the
//!   MCM's Cartesian poses). It is not ROS-Industrial's `flange` (x out of the flange).
//! - `{prefix}tool0`: the same frame as `flange`: z along the last axis, out of the flange
//!   (the P-Rob2's d6 > 0), as ROS-Industrial's `tool0` wants. The TCP of `[arm.tool]` (and of
//!   `set_tool`) is not in the description: nothing offsets `tool0`.
//!
//! # Joints
//! Revolute joints named `{prefix}` + the axis's `name` (the names of `/joint_states`), axis z,
//! limits in SI units: `min_deg`/`max_deg` in rad, `max_velocity_deg_s` in rad/s, effort the
//! peak joint torque `max_current_a × torque_per_amp()` in N·m; `<dynamics>` carries the joint
//! friction (`viscous_friction_nm_s_rad`, `coulomb_friction_nm`). URDF 1.0 has no acceleration
//! limit: `max_acceleration_deg_s2` is not in the description. URDF keeps joint and link names
//! apart: the P-Rob2's sixth axis, `flange`, names a joint beside the link `flange`.
//!
//! # Inertials
//! Each link's mass, centre of mass and principal inertia, moved from its DH frame into the
//! URDF link frame. The configured tool (`[arm.tool]`: its mass at its centre of mass in frame
//! 6, with its inertia) is lumped into `link_6` as `ArmModel` lumps it (combined mass, centre of
//! mass, parallel-axis theorem).
//!
//! # Geometry
//! Schematic: cylinders along the DH lengths d and a and one around each joint axis, so that
//! RViz shows the arm's kinematic skeleton. They are not the arm's real shape; the collision
//! elements are the same cylinders and are no safety envelope.

use mcm_shared::NUM_AXES;
use mcm_shared::config::{LinkConfig, RobotConfig, ToolConfig};
use nalgebra::{Matrix3, Vector3};
use std::path::{Path, PathBuf};

/// How the description is named.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct UrdfOptions {
    /// Put before every link, joint and material name, for several arms in one ROS graph
    /// (e.g. `"left_"`). Empty by default.
    pub prefix: String,
}

/// Why no description was generated from a configuration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UrdfError {
    #[error("the URDF needs exactly {NUM_AXES} `{key}` tables; the configuration has {found}")]
    WrongCount { key: &'static str, found: usize },
    #[error("axis[{axis}].name is empty; the URDF names joint {axis} after it")]
    EmptyAxisName { axis: usize },
    #[error(
        "the URDF would have two joints named `{name}`: the axes' names (with the prefix) must \
         differ from each other and from the fixed joints `{prefix}link_{NUM_AXES}-flange` and \
         `{prefix}flange-tool0`"
    )]
    DuplicateJointName { name: String, prefix: String },
    #[error("{what} is {value}; the URDF needs a finite number there")]
    NotFinite { what: String, value: f64 },
}

/// Why the description was not written to its file.
#[derive(Debug, thiserror::Error)]
pub enum UrdfWriteError {
    #[error("cannot write the URDF to {}: {source}", path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot move the URDF written to {} onto {}: {source}", from.display(), to.display())]
    Rename {
        from: PathBuf,
        to: PathBuf,
        source: std::io::Error,
    },
}

/// The URDF of the arm described by `cfg`, names prefixed by `opts.prefix`.
///
/// A configuration that `RobotConfig::validate` accepts gives a description unless two axes
/// share a name or one has none (the configuration does not check names).
pub fn generate(cfg: &RobotConfig, opts: &UrdfOptions) -> Result<String, UrdfError> {
    if cfg.axes.len() != NUM_AXES {
        return Err(UrdfError::WrongCount {
            key: "[[axis]]",
            found: cfg.axes.len(),
        });
    }
    if cfg.arm.links.len() != NUM_AXES {
        return Err(UrdfError::WrongCount {
            key: "[[arm.link]]",
            found: cfg.arm.links.len(),
        });
    }
    let p = &opts.prefix;
    let joint_names = joint_names(cfg, p)?;
    let radius = schematic_radius(&cfg.arm.links);

    let mut x = Xml::default();
    x.line(0, r#"<?xml version="1.0"?>"#);
    x.line(
        0,
        "<!-- Generated by mcm-ros2 from the robot configuration: change the configuration, \
         not this file. Geometry is schematic. -->",
    );
    x.line(0, &format!(r#"<robot name="{}">"#, esc(&cfg.robot.name)));
    x.line(
        1,
        &format!(r#"<material name="{}">"#, esc(&material(p, LINK))),
    );
    x.line(2, r#"<color rgba="0.75 0.75 0.78 1"/>"#);
    x.line(1, "</material>");
    x.line(
        1,
        &format!(r#"<material name="{}">"#, esc(&material(p, JOINT))),
    );
    x.line(2, r#"<color rgba="0.25 0.3 0.4 1"/>"#);
    x.line(1, "</material>");

    x.link_open(&format!("{p}base_link"));
    x.cylinder(
        p,
        LINK,
        [0.0, 0.0, radius],
        [0.0; 3],
        mm(1.5 * radius),
        mm(2.0 * radius),
    );
    x.line(1, "</link>");

    let mut parent = format!("{p}base_link");
    let mut origin = Pose::IDENTITY;
    for (i, ((axis, link), joint)) in cfg
        .axes
        .iter()
        .zip(&cfg.arm.links)
        .zip(&joint_names)
        .enumerate()
    {
        let n = i + 1;
        let child = format!("{p}link_{n}");
        let lower = axis.min_deg.to_radians();
        let upper = axis.max_deg.to_radians();
        let velocity = axis.max_velocity_deg_s.to_radians();
        let effort = axis.max_current_a * axis.torque_per_amp();
        finite(
            || {
                format!(
                    "axis[{n}]'s limits (min_deg, max_deg, max_velocity_deg_s, \
                     max_current_a x torque_per_amp)"
                )
            },
            &[lower, upper, velocity, effort],
        )?;
        let (damping, friction) = (axis.viscous_friction_nm_s_rad, axis.coulomb_friction_nm);
        finite(
            || format!("axis[{n}]'s friction (viscous_friction_nm_s_rad, coulomb_friction_nm)"),
            &[damping, friction],
        )?;

        x.line(
            1,
            &format!(r#"<joint name="{}" type="revolute">"#, esc(joint)),
        );
        x.joint_body(&origin, &parent, &child);
        x.line(2, r#"<axis xyz="0 0 1"/>"#);
        x.line(
            2,
            &format!(
                r#"<limit lower="{}" upper="{}" effort="{}" velocity="{}"/>"#,
                num(lower),
                num(upper),
                num(effort),
                num(velocity)
            ),
        );
        x.line(
            2,
            &format!(
                r#"<dynamics damping="{}" friction="{}"/>"#,
                num(damping),
                num(friction)
            ),
        );
        x.line(1, "</joint>");

        let next = dh_fixed(link);
        finite(
            || format!("arm.link[{n}]'s geometry (d, a, alpha_deg, offset_deg)"),
            &[next.xyz, next.rpy].concat(),
        )?;
        let (mass, com, inertia) = if n == NUM_AXES {
            lumped_with_tool(link, &cfg.arm.tool)
        } else {
            (
                link.mass,
                Vector3::from(link.com),
                Matrix3::from_diagonal(&Vector3::from(link.inertia)),
            )
        };
        // From the DH frame of link n into the frame of joint n: x_L = R x_DH + p.
        let r = dh_rotation(link);
        let com = r * com + Vector3::from(next.xyz);
        let inertia = r * inertia * r.transpose();
        let inertia = [
            inertia[(0, 0)],
            inertia[(0, 1)],
            inertia[(0, 2)],
            inertia[(1, 1)],
            inertia[(1, 2)],
            inertia[(2, 2)],
        ];
        finite(
            || {
                let tool = if n == NUM_AXES { " with arm.tool" } else { "" };
                format!("arm.link[{n}]'s inertial (mass, com, inertia){tool}")
            },
            &[&[mass][..], com.as_slice(), &inertia].concat(),
        )?;

        x.link_open(&child);
        x.line(2, "<inertial>");
        x.line(
            3,
            &format!(r#"<origin xyz="{}" rpy="0 0 0"/>"#, v3(com.into())),
        );
        x.line(3, &format!(r#"<mass value="{}"/>"#, num(mass)));
        x.line(
            3,
            &format!(
                r#"<inertia ixx="{}" ixy="{}" ixz="{}" iyy="{}" iyz="{}" izz="{}"/>"#,
                num(inertia[0]),
                num(inertia[1]),
                num(inertia[2]),
                num(inertia[3]),
                num(inertia[4]),
                num(inertia[5])
            ),
        );
        x.line(2, "</inertial>");
        x.link_geometry(p, link, radius);
        x.line(1, "</link>");

        parent = child;
        origin = next;
    }

    let flange = format!("{p}flange");
    x.line(
        1,
        &format!(r#"<joint name="{}" type="fixed">"#, esc(&flange_joint(p))),
    );
    x.joint_body(&origin, &parent, &flange);
    x.line(1, "</joint>");
    x.line(1, &format!(r#"<link name="{}"/>"#, esc(&flange)));
    let tool0 = format!("{p}tool0");
    x.line(
        1,
        &format!(r#"<joint name="{}" type="fixed">"#, esc(&tool0_joint(p))),
    );
    x.joint_body(&Pose::IDENTITY, &flange, &tool0);
    x.line(1, "</joint>");
    x.line(1, &format!(r#"<link name="{}"/>"#, esc(&tool0)));
    x.line(0, "</robot>");
    Ok(x.out)
}

/// Write `urdf` to `path`, replacing the file whole (written next to it, then renamed), so that
/// a reader never sees half a description.
pub fn write(path: &Path, urdf: &str) -> Result<(), UrdfWriteError> {
    let mut tmp_name = path.file_name().unwrap_or_default().to_os_string();
    tmp_name.push(format!(".tmp{}", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    std::fs::write(&tmp, urdf).map_err(|source| UrdfWriteError::Write {
        path: path.to_path_buf(),
        source,
    })?;
    std::fs::rename(&tmp, path).map_err(|source| {
        // Best effort: the rename's error is the one to report.
        let _ = std::fs::remove_file(&tmp);
        UrdfWriteError::Rename {
            from: tmp.clone(),
            to: path.to_path_buf(),
            source,
        }
    })
}

const LINK: &str = "link";
const JOINT: &str = "joint";

fn material(prefix: &str, what: &str) -> String {
    format!("{prefix}mcm_{what}")
}

/// The fixed joint above `flange`.
fn flange_joint(prefix: &str) -> String {
    format!("{prefix}link_{NUM_AXES}-flange")
}

/// The fixed joint above `tool0`.
fn tool0_joint(prefix: &str) -> String {
    format!("{prefix}flange-tool0")
}

/// The revolute joints' names, checked non-empty and distinct from each other and from the
/// fixed joints'.
fn joint_names(cfg: &RobotConfig, prefix: &str) -> Result<Vec<String>, UrdfError> {
    let mut names: Vec<String> = Vec::with_capacity(NUM_AXES);
    for (i, axis) in cfg.axes.iter().enumerate() {
        if axis.name.is_empty() {
            return Err(UrdfError::EmptyAxisName { axis: i + 1 });
        }
        let name = format!("{prefix}{}", axis.name);
        if names.contains(&name) || name == flange_joint(prefix) || name == tool0_joint(prefix) {
            return Err(UrdfError::DuplicateJointName {
                name,
                prefix: prefix.to_string(),
            });
        }
        names.push(name);
    }
    Ok(names)
}

fn finite(what: impl FnOnce() -> String, values: &[f64]) -> Result<(), UrdfError> {
    match values.iter().find(|v| !v.is_finite()) {
        None => Ok(()),
        Some(&value) => Err(UrdfError::NotFinite {
            what: what(),
            value,
        }),
    }
}

/// An origin: translation [m] and URDF roll-pitch-yaw [rad].
#[derive(Debug, Clone, Copy, PartialEq)]
struct Pose {
    xyz: [f64; 3],
    rpy: [f64; 3],
}

impl Pose {
    const IDENTITY: Pose = Pose {
        xyz: [0.0; 3],
        rpy: [0.0; 3],
    };
}

/// sin and cos of an angle in degrees, exact at multiples of 90° (the description then says
/// 0 where the geometry has 0, not 6e-17; elsewhere the same values as `f64::sin_cos`).
fn sin_cos_deg(deg: f64) -> (f64, f64) {
    match deg.rem_euclid(360.0) {
        0.0 => (0.0, 1.0),
        90.0 => (1.0, 0.0),
        180.0 => (0.0, -1.0),
        270.0 => (-1.0, 0.0),
        _ => deg.to_radians().sin_cos(),
    }
}

/// The fixed part of link `l`'s DH transform, Rz(offset) Tz(d) Tx(a) Rx(alpha), as an origin.
fn dh_fixed(l: &LinkConfig) -> Pose {
    let (so, co) = sin_cos_deg(l.offset_deg);
    Pose {
        xyz: [l.a * co, l.a * so, l.d],
        rpy: [l.alpha_deg.to_radians(), 0.0, l.offset_deg.to_radians()],
    }
}

/// The rotation of [`dh_fixed`]: Rz(offset) Rx(alpha).
fn dh_rotation(l: &LinkConfig) -> Matrix3<f64> {
    let (so, co) = sin_cos_deg(l.offset_deg);
    let (sa, ca) = sin_cos_deg(l.alpha_deg);
    #[rustfmt::skip]
    let r = Matrix3::new(
        co, -so * ca,  so * sa,
        so,  co * ca, -co * sa,
        0.0,      sa,       ca,
    );
    r
}

/// Link `l` with the tool (its mass at its centre of mass, with its own inertia, in the link's
/// DH frame) lumped in, as `ArmModel::set_tool` does: (mass, centre of mass, inertia about it).
/// The values as configured, unchecked: a value that is not finite is refused where the
/// inertial is written.
fn lumped_with_tool(l: &LinkConfig, tool: &ToolConfig) -> (f64, Vector3<f64>, Matrix3<f64>) {
    let tool_mass = tool.mass;
    let tool_com = Vector3::from(tool.com);
    let [ixx, iyy, izz, ixy, ixz, iyz] = tool.inertia.unwrap_or([0.0; 6]);
    #[rustfmt::skip]
    let tool_inertia = Matrix3::new(
        ixx, ixy, ixz,
        ixy, iyy, iyz,
        ixz, iyz, izz,
    );
    let c_link = Vector3::from(l.com);
    let m = l.mass + tool_mass;
    let c = (c_link * l.mass + tool_com * tool_mass) / m;
    // Parallel-axis theorem: a point mass m at offset r adds m (|r|² I − r rᵀ).
    let shift = |mass: f64, r: Vector3<f64>| {
        (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * mass
    };
    let inertia = Matrix3::from_diagonal(&Vector3::from(l.inertia))
        + shift(l.mass, c_link - c)
        + tool_inertia
        + shift(tool_mass, tool_com - c);
    (m, c, inertia)
}

/// Radius of the schematic cylinders: a twenty-fifth of the arm's DH lengths, at least 1 cm.
fn schematic_radius(links: &[LinkConfig]) -> f64 {
    let reach: f64 = links.iter().map(|l| l.a.abs() + l.d.abs()).sum();
    mm(reach / 25.0).max(0.01)
}

/// A schematic size rounded to the millimetre, for a readable description.
fn mm(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// Shorter DH lengths get no cylinder.
const MIN_SEGMENT_M: f64 = 1e-6;

/// The description being written, two spaces per level.
#[derive(Default)]
struct Xml {
    out: String,
}

impl Xml {
    fn line(&mut self, level: usize, text: &str) {
        for _ in 0..level {
            self.out.push_str("  ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn link_open(&mut self, name: &str) {
        self.line(1, &format!(r#"<link name="{}">"#, esc(name)));
    }

    /// A joint's origin, parent and child.
    fn joint_body(&mut self, origin: &Pose, parent: &str, child: &str) {
        self.line(
            2,
            &format!(
                r#"<origin xyz="{}" rpy="{}"/>"#,
                v3(origin.xyz),
                v3(origin.rpy)
            ),
        );
        self.line(2, &format!(r#"<parent link="{}"/>"#, esc(parent)));
        self.line(2, &format!(r#"<child link="{}"/>"#, esc(child)));
    }

    /// One schematic cylinder (along z of its origin), as a visual and the same collision.
    fn cylinder(
        &mut self,
        prefix: &str,
        what: &str,
        xyz: [f64; 3],
        rpy: [f64; 3],
        radius: f64,
        length: f64,
    ) {
        let geometry = format!(
            r#"<cylinder radius="{}" length="{}"/>"#,
            num(radius),
            num(length)
        );
        let origin = format!(r#"<origin xyz="{}" rpy="{}"/>"#, v3(xyz), v3(rpy));
        for element in ["visual", "collision"] {
            self.line(2, &format!("<{element}>"));
            self.line(3, &origin);
            self.line(3, "<geometry>");
            self.line(4, &geometry);
            self.line(3, "</geometry>");
            if element == "visual" {
                self.line(
                    3,
                    &format!(r#"<material name="{}"/>"#, esc(&material(prefix, what))),
                );
            }
            self.line(2, &format!("</{element}>"));
        }
    }

    /// Link `l` in the frame of its joint: a housing around the joint axis, a cylinder along d
    /// (the joint axis) and one along a (towards the next joint).
    fn link_geometry(&mut self, prefix: &str, l: &LinkConfig, radius: f64) {
        self.cylinder(
            prefix,
            JOINT,
            [0.0; 3],
            [0.0; 3],
            mm(1.2 * radius),
            mm(2.4 * radius),
        );
        if l.d.abs() > MIN_SEGMENT_M {
            let xyz = [0.0, 0.0, l.d / 2.0];
            self.cylinder(prefix, LINK, xyz, [0.0; 3], radius, l.d.abs());
        }
        if l.a.abs() > MIN_SEGMENT_M {
            let (so, co) = sin_cos_deg(l.offset_deg);
            // The cylinder's z turned onto x (pitch π/2), then x onto the offset's direction.
            let xyz = [l.a * co / 2.0, l.a * so / 2.0, l.d];
            let rpy = [0.0, std::f64::consts::FRAC_PI_2, l.offset_deg.to_radians()];
            self.cylinder(prefix, LINK, xyz, rpy, radius, l.a.abs());
        }
    }
}

/// A number as Rust's shortest text that reads back to the same `f64` (0 for ±0).
fn num(x: f64) -> String {
    if x == 0.0 { "0".into() } else { format!("{x}") }
}

fn v3(v: [f64; 3]) -> String {
    format!("{} {} {}", num(v[0]), num(v[1]), num(v[2]))
}

/// `s` made safe inside an XML attribute value.
fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests;
