//! The commands of the protocol, one file each: the typed arguments (those that travel to the
//! real-time core are the types of [`crate::command`]), how they are read from and written to
//! JSON, the requests that carry them to the core, and the command's [`super::CommandDef`].
//! Not used inside the real-time cycle.

pub mod authenticate;
pub mod calibrate;
pub mod hold;
pub mod identify_payload;
pub mod info;
pub mod inverse_kinematics;
pub mod move_all;
pub mod move_axis;
pub mod move_linear;
pub mod move_to_pose;
pub mod pvt;
pub mod pvt_points;
pub mod release;
pub mod release_control;
pub mod set_cartesian_velocity;
pub mod set_tool;
pub mod set_torques;
pub mod set_velocities;
pub mod sim;
pub mod sleep;
pub mod status;
pub mod take_control;
pub mod torque_control;
pub mod velocity_control;

/// What every command file uses.
mod prelude {
    pub(crate) use crate::command::Request;
    pub(crate) use crate::config::RobotConfig;
    pub(crate) use crate::mode::CommandKind;
    pub(crate) use crate::protocol::spec::{
        CommandDef, Group, IN_HOLD, Kind, Success, TO_HOLD, TO_PVT, arg,
    };
    pub(crate) use crate::protocol::{Args, CommandError, Definition};
    pub(crate) use crate::ranges::Arg;
    pub(crate) use serde_json::{Map, Value};
}
