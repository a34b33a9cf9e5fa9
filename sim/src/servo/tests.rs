use super::*;

#[test]
fn interpolates_linearly_over_the_period() {
    let mut s = Servo::new(ServoGains::for_armature(0.1));
    s.hold(1.0);
    assert_eq!(s.setpoint(0.5), (1.0, 0.0));
    s.new_segment(1.01, 0.005);
    let (p, v) = s.setpoint(0.5);
    assert!(
        (p - 1.005).abs() < 1e-12 && (v - 2.0).abs() < 1e-9,
        "{p} {v}"
    );
    s.new_segment(1.01, 0.005);
    assert_eq!(s.setpoint(0.0), (1.01, 0.0));
}

#[test]
fn pid_is_clamped_and_does_not_wind_up() {
    let mut s = Servo::new(ServoGains {
        kp: 100.0,
        ki: 1000.0,
        kd: 0.0,
    });
    for _ in 0..10_000 {
        assert_eq!(s.torque(1.0, 0.0, 0.0, 0.0, 0.001, 5.0), 5.0);
    }
    // once the error reverses, the output leaves saturation at once (no wound-up integral)
    let u = s.torque(0.0, 0.0, 0.01, 0.0, 0.001, 5.0);
    assert!(u < 5.0, "{u}");
}

#[test]
fn integral_removes_a_constant_load() {
    // unit inertia with a constant load of 2 Nm, explicit integration
    let mut s = Servo::new(ServoGains::for_armature(0.15));
    let (mut p, mut v, dt) = (0.0, 0.0, 0.0005);
    for _ in 0..20_000 {
        let tau = s.torque(0.0, 0.0, p, v, dt, 100.0) - 2.0;
        v += tau / 0.5 * dt;
        p += v * dt;
    }
    assert!(p.abs() < 1e-9 && v.abs() < 1e-9, "{p} {v}");
}

#[test]
fn quick_stop_ramps_to_rest() {
    let mut s = Servo::new(ServoGains::for_armature(0.1));
    s.start_quick_stop(0.0, 1.0);
    let mut steps = 0;
    let (p, _, done) = loop {
        steps += 1;
        let r = s.quick_stop_step(10.0, 0.001);
        if r.2 {
            break r;
        }
    };
    assert!(done && (100..=101).contains(&steps), "{steps}");
    assert!((p - 0.05).abs() < 1e-6, "v^2 / 2a = 0.05 rad, got {p}");
}
