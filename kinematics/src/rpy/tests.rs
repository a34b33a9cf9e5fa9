use super::*;
use nalgebra::{Quaternion, Unit, Vector3};

fn rotation(axis: Vector3<f64>, deg: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Unit::new_normalize(axis), deg.to_radians())
}

fn angle(a: [f64; 4], b: &UnitQuaternion<f64>) -> f64 {
    let [x, y, z, w] = a;
    UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)).angle_to(b)
}

#[test]
fn fixed_axes_x_then_y_then_z() {
    let (r, p, y) = (30.0, -20.0, 75.0);
    // R = Rz(yaw) Ry(pitch) Rx(roll): the URDF's rpy.
    let expected =
        rotation(Vector3::z(), y) * rotation(Vector3::y(), p) * rotation(Vector3::x(), r);
    let q = quaternion_from_rpy_deg([r, p, y]);
    assert!(angle(q, &expected) < 1e-12, "{q:?}");
    assert!(q[3] >= 0.0);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert_eq!(
        quaternion_from_rpy_deg([0.0, 0.0, 0.0]),
        [0.0, 0.0, 0.0, 1.0]
    );
    let yaw = quaternion_from_rpy_deg([0.0, 0.0, 90.0]);
    assert!(
        (yaw[2] - h).abs() < 1e-15 && (yaw[3] - h).abs() < 1e-15,
        "{yaw:?}"
    );
    // A half turn keeps w >= 0.
    let flip = quaternion_from_rpy_deg([180.0, 0.0, 0.0]);
    assert!(
        (flip[0].abs() - 1.0).abs() < 1e-15 && flip[3] >= 0.0,
        "{flip:?}"
    );
}

#[test]
fn back_and_forth_gives_the_same_angles_away_from_pitch_90() {
    for rpy in [
        [10.0, 20.0, 30.0],
        [-170.0, 89.0, 179.0],
        [180.0, 0.0, 0.0],
        [45.0, -60.0, -135.0],
    ] {
        let back = rpy_deg_from_quaternion(quaternion_from_rpy_deg(rpy));
        for i in 0..3 {
            assert!((back[i] - rpy[i]).abs() < 1e-9, "{rpy:?} -> {back:?}");
        }
    }
    // At pitch 90 the rotation is kept, not the split between roll and yaw.
    let q = quaternion_from_rpy_deg([20.0, 90.0, 30.0]);
    let back = quaternion_from_rpy_deg(rpy_deg_from_quaternion(q));
    let [x, y, z, w] = q;
    assert!(
        angle(
            back,
            &UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z))
        ) < 1e-7
    );
}
