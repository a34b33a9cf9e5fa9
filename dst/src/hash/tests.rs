use super::*;

fn hash_of(s: &StateSample, replies: &[Reply]) -> u64 {
    let mut h = RunHash::default();
    h.cycle(s, replies);
    h.value()
}

#[test]
fn every_field_of_the_state_and_of_a_reply_changes_the_hash() {
    let s = StateSample::default();
    let r = Reply::default();
    let base = hash_of(&s, &[r]);
    type Change = fn(&mut StateSample, &mut Reply);
    let changes: [(&str, Change); 36] = [
        ("seq", |s, _| s.seq = 1),
        ("t_ns", |s, _| s.t_ns = 1),
        ("mode", |s, _| s.mode = 1),
        ("flags", |s, _| s.flags = 1),
        ("position", |s, _| s.position[5] = 1.0),
        ("velocity", |s, _| s.velocity[5] = 1.0),
        ("acceleration", |s, _| s.acceleration[5] = 1.0),
        ("current", |s, _| s.current[5] = 1.0),
        ("measured_position", |s, _| s.measured_position[5] = 1.0),
        ("commanded_position", |s, _| s.commanded_position[5] = 1.0),
        ("following_error", |s, _| s.following_error[5] = 1.0),
        ("i2t", |s, _| s.i2t[5] = 1.0),
        ("sim_true_position", |s, _| s.sim_true_position[5] = 1.0),
        ("sim_true_velocity", |s, _| s.sim_true_velocity[5] = 1.0),
        ("axis_flags", |s, _| s.axis_flags[5] = 1),
        ("pvt_queued", |s, _| s.pvt_queued = 1),
        ("pvt_capacity", |s, _| s.pvt_capacity = 1),
        ("command_receive_errors", |s, _| {
            s.command_receive_errors = 1
        }),
        ("timing.period_ns", |s, _| s.timing.period_ns = 1),
        ("timing.recent.max_ns", |s, _| s.timing.recent.max_ns = 1),
        ("timing.since_start.cycles", |s, _| {
            s.timing.since_start.cycles = 1
        }),
        ("last_error.seq", |s, _| s.last_error.seq = 1),
        ("last_error.code", |s, _| s.last_error.code = 1),
        ("last_error.values", |s, _| s.last_error.values[3] = 1.0),
        ("reply_head", |s, _| s.reply_head = 1),
        ("owner_client_id", |s, _| s.owner_client_id = 1),
        ("cartesian.position", |s, _| s.cartesian.position[2] = 1.0),
        ("cartesian.orientation", |s, _| {
            s.cartesian.orientation[3] = 1.0
        }),
        ("cartesian.linear_velocity", |s, _| {
            s.cartesian.linear_velocity[0] = 1.0
        }),
        ("cartesian.angular_velocity", |s, _| {
            s.cartesian.angular_velocity[1] = 1.0
        }),
        ("reply.seq", |_, r| r.seq = 1),
        ("reply.cycle", |_, r| r.cycle = 1),
        ("reply.kind", |_, r| r.kind = 1),
        ("reply.status", |_, r| r.status = 1),
        ("reply.axis", |_, r| r.axis = 1),
        ("reply.values", |_, r| r.values[0] = 1.0),
    ];
    for (name, change) in changes {
        let (mut s2, mut r2) = (s, r);
        change(&mut s2, &mut r2);
        assert_ne!(hash_of(&s2, &[r2]), base, "{name} is not hashed");
    }
    assert_ne!(hash_of(&s, &[]), base, "the number of replies is hashed");
}

#[test]
fn the_first_diverging_cycle_is_named() {
    assert_eq!(first_divergence(&[1, 2, 3], &[1, 2, 3]), None);
    assert_eq!(first_divergence(&[1, 2, 3], &[1, 9, 3]), Some(2));
    assert_eq!(first_divergence(&[1, 2, 3], &[1, 2]), Some(3));
    let mut a = RunHash::default();
    let mut b = RunHash::default();
    let mut s = StateSample::default();
    for seq in 1..=3 {
        s.seq = seq;
        a.cycle(&s, &[]);
        s.current[2] = if seq == 2 { 0.5 } else { 0.0 };
        b.cycle(&s, &[]);
        s.current[2] = 0.0;
    }
    assert_eq!(first_divergence(a.checkpoints(), b.checkpoints()), Some(2));
}
