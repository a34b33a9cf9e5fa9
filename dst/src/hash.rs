//! The hash of a run, for replay: every field of every cycle's published state
//! ([`StateSample`], its [`CycleTiming`] and [`ErrorRecord`] included) and of its replies
//! ([`Reply`]), and a checkpoint after every cycle, so that two runs of a seed that differ
//! name the first cycle they differ in ([`first_divergence`]).
//!
//! Nothing is left out: in virtual time every field is deterministic. The timing figures that
//! the real-time loop measures with the wall clock (latencies, work time, overruns) are zero
//! there, `period_ns` and `work_budget_ns` are configuration (`CycleClock::virtual_time`), and
//! an error's `unix_ns` is 0. The fields are taken apart without `..`, so that a field added to
//! the state or a reply does not compile until it is hashed here.

use mcm_shared::sample::{
    BusCounters, CycleTiming, ErrorRecord, LatencyFigures, Reply, StateSample, TcpState, ToolState,
};

/// FNV-1a over 64-bit words, with a checkpoint after every cycle.
#[derive(Debug, Clone)]
pub struct RunHash {
    h: u64,
    /// The hash after each cycle (index 0: after the first cycle).
    checkpoints: Vec<u64>,
}

impl Default for RunHash {
    fn default() -> Self {
        RunHash {
            h: 0xCBF2_9CE4_8422_2325,
            checkpoints: Vec::new(),
        }
    }
}

impl RunHash {
    /// The hash so far.
    pub fn value(&self) -> u64 {
        self.h
    }

    /// The hash after each cycle so far.
    pub fn checkpoints(&self) -> &[u64] {
        &self.checkpoints
    }

    /// One cycle: its state and its replies.
    pub fn cycle(&mut self, s: &StateSample, replies: &[Reply]) {
        self.state(s);
        self.word(replies.len() as u64);
        for r in replies {
            self.reply(r);
        }
        self.checkpoints.push(self.h);
    }

    fn word(&mut self, w: u64) {
        for b in w.to_le_bytes() {
            self.h ^= u64::from(b);
            self.h = self.h.wrapping_mul(0x0000_0100_0000_01B3);
        }
    }

    fn floats(&mut self, a: &[f64]) {
        for x in a {
            self.word(x.to_bits());
        }
    }

    fn state(&mut self, s: &StateSample) {
        let StateSample {
            seq,
            t_ns,
            mode,
            flags,
            position,
            velocity,
            acceleration,
            current,
            measured_position,
            commanded_position,
            following_error,
            i2t,
            sim_true_position,
            sim_true_velocity,
            axis_flags,
            pvt_queued,
            pvt_capacity,
            command_receive_errors,
            timing,
            last_error,
            reply_head,
            owner_client_id,
            bus,
            cartesian,
            tool,
        } = s;
        for w in [*seq, *t_ns, u64::from(*mode), u64::from(*flags)] {
            self.word(w);
        }
        for a in [
            position,
            velocity,
            acceleration,
            current,
            measured_position,
            commanded_position,
            following_error,
            i2t,
            sim_true_position,
            sim_true_velocity,
        ] {
            self.floats(a);
        }
        for f in axis_flags {
            self.word(u64::from(*f));
        }
        for w in [
            u64::from(*pvt_queued),
            u64::from(*pvt_capacity),
            *command_receive_errors,
            *reply_head,
            *owner_client_id,
        ] {
            self.word(w);
        }
        let BusCounters {
            bad_frames,
            frames_dropped,
            events_dropped,
            bus_errors,
        } = bus;
        for w in [*bad_frames, *frames_dropped, *events_dropped, *bus_errors] {
            self.word(w);
        }
        self.timing(timing);
        self.error(last_error);
        let TcpState {
            position,
            orientation,
            linear_velocity,
            angular_velocity,
        } = cartesian;
        for a in [
            &position[..],
            orientation,
            linear_velocity,
            angular_velocity,
        ] {
            self.floats(a);
        }
        let ToolState {
            tcp_position,
            tcp_orientation,
            mass,
            center_of_mass,
            inertia,
        } = tool;
        self.floats(tcp_position);
        self.floats(tcp_orientation);
        self.floats(&[*mass]);
        self.floats(center_of_mass);
        self.floats(inertia);
    }

    fn timing(&mut self, t: &CycleTiming) {
        let CycleTiming {
            period_ns,
            overruns,
            since_start,
            recent,
            recent_window_ns,
            work_max_ns,
            work_budget_ns,
            over_budget,
        } = t;
        for w in [
            *period_ns,
            *overruns,
            *recent_window_ns,
            *work_max_ns,
            *work_budget_ns,
            *over_budget,
        ] {
            self.word(w);
        }
        self.latency(since_start);
        self.latency(recent);
    }

    fn latency(&mut self, l: &LatencyFigures) {
        let LatencyFigures {
            p50_ns,
            p99_ns,
            p99_9_ns,
            p99_99_ns,
            max_ns,
            cycles,
        } = l;
        for w in [*p50_ns, *p99_ns, *p99_9_ns, *p99_99_ns, *max_ns, *cycles] {
            self.word(w);
        }
    }

    fn error(&mut self, e: &ErrorRecord) {
        let ErrorRecord {
            seq,
            cycle,
            unix_ns,
            code,
            axis,
            values,
        } = e;
        for w in [*seq, *cycle, *unix_ns, u64::from(*code), u64::from(*axis)] {
            self.word(w);
        }
        self.floats(values);
    }

    fn reply(&mut self, r: &Reply) {
        let Reply {
            seq,
            client_id,
            request_id,
            cycle,
            kind,
            status,
            code,
            axis,
            values,
        } = r;
        for w in [
            *seq,
            *client_id,
            *request_id,
            *cycle,
            u64::from(*kind),
            u64::from(*status),
            u64::from(*code),
            u64::from(*axis),
        ] {
            self.word(w);
        }
        self.floats(values);
    }
}

/// The first cycle (1-based, as the state's `seq` and a violation count them) after which two
/// runs' checkpoints differ, or after which one run went on and the other did not; `None` when
/// they are the same.
pub fn first_divergence(a: &[u64], b: &[u64]) -> Option<u64> {
    let n = a.iter().zip(b).position(|(x, y)| x != y);
    match n {
        Some(i) => Some(i as u64 + 1),
        None if a.len() != b.len() => Some(a.len().min(b.len()) as u64 + 1),
        None => None,
    }
}

#[cfg(test)]
mod tests;
