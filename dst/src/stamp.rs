//! What the senders of a run (the clients, the driver, the fault injector, the quiet phase's
//! client) share: their commands stamped with the client id and the next request id
//! ([`Stamp`]), and the calibration of all axes that the driver and the quiet phase's client
//! ask for ([`calibrate_all`]).

use mcm_shared::command::{Calibrate, Direction, Request, Which};
use mcm_shared::sample::CommandSample;

/// A client's identity on its commands: its id, and its request ids 1, 2, 3, ...
#[derive(Debug, Clone)]
pub struct Stamp {
    pub client_id: u64,
    next_request: u64,
}

impl Stamp {
    pub fn new(client_id: u64) -> Stamp {
        Stamp {
            client_id,
            next_request: 1,
        }
    }

    /// `sample` with this client's id and its next request id.
    pub fn stamp(&mut self, mut sample: CommandSample) -> CommandSample {
        sample.client_id = self.client_id;
        sample.request_id = self.next_request;
        self.next_request += 1;
        sample
    }

    /// `r` encoded and stamped.
    pub fn request(&mut self, r: Request) -> CommandSample {
        self.stamp(r.encode())
    }
}

/// `calibrate` of all axes, in the configured search directions, without forcing the
/// mechanical stop.
pub fn calibrate_all() -> Request {
    Request::Calibrate(Calibrate {
        which: Which::All,
        elbow_direction: Direction::Positive,
        wrist_direction: Direction::Positive,
        force_mechanical_stop: false,
    })
}
