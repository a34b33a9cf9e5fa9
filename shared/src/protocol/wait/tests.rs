use super::*;
use crate::command::{Calibrate, MoveAxis};
use crate::protocol::{Hold, Sleep};

#[test]
fn calibrate_and_sleep_may_take_longer_than_any_other_command() {
    let calibrate = Command::Calibrate(Calibrate {
        which: crate::protocol::DEFAULT_WHICH,
        elbow_direction: Default::default(),
        wrist_direction: Default::default(),
        force_mechanical_stop: false,
    });
    assert_eq!(calibrate.reply_within(), CALIBRATION_TIMEOUT);
    assert_eq!(
        calibrate.extra_reply_time(),
        CALIBRATION_TIMEOUT - REPLY_TIMEOUT
    );
    let identify = Command::IdentifyPayload(crate::command::IdentifyPayload { apply: false });
    assert_eq!(identify.reply_within(), IDENTIFY_PAYLOAD_TIMEOUT);
    assert!(IDENTIFY_PAYLOAD_TIMEOUT >= Duration::from_secs(30));
    let hour = Duration::from_secs(3600);
    let sleep = Command::Sleep(Sleep { duration: hour });
    assert_eq!(sleep.reply_within(), hour);
    assert_eq!(sleep.extra_reply_time(), hour - REPLY_TIMEOUT);
    let short = Command::Sleep(Sleep {
        duration: Duration::from_secs(1),
    });
    assert_eq!(short.extra_reply_time(), Duration::ZERO);
    let move_axis = Command::MoveAxis(MoveAxis {
        axis: crate::command::Axis::ALL[0],
        target_deg: 0.0,
        velocity_factor: 0.5,
    });
    for c in [Command::Hold(Hold), move_axis] {
        assert_eq!(c.reply_within(), REPLY_TIMEOUT, "{c:?}");
        assert_eq!(c.extra_reply_time(), Duration::ZERO);
    }
}
