use super::*;

#[test]
fn round_trip() {
    let d = [0.0, 90.0, -45.0, 180.0, 1e-3, -170.0];
    let back = rad_to_deg6(&deg_to_rad6(&d));
    for (a, b) in d.iter().zip(back) {
        assert!((a - b).abs() < 1e-12);
    }
    assert!((deg_to_rad(180.0) - core::f64::consts::PI).abs() < 1e-15);
}
