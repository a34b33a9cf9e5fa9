use super::*;

fn tool(tcp: Tcp, mass: f64, com: [f64; 3], inertia: Option<[f64; 6]>) -> Result<Tool, ToolError> {
    Tool::new(tcp, mass, com, inertia)
}

#[test]
fn a_valid_tool_is_kept_and_its_orientation_normalised() {
    let tcp = Tcp {
        position: [0.0, 0.0, 0.15],
        orientation: [0.0, 0.0, 0.0, 1.0005],
    };
    let t = tool(
        tcp,
        2.0,
        [0.0, 0.0, 0.06],
        Some([0.01, 0.01, 0.005, 0.0, 0.0, 0.0]),
    )
    .unwrap();
    assert_eq!(t.tcp.orientation, [0.0, 0.0, 0.0, 1.0]);
    assert_eq!(t.tcp.position, [0.0, 0.0, 0.15]);
    assert_eq!(t.mass, 2.0);
    assert_eq!(t.inertia, [0.01, 0.01, 0.005, 0.0, 0.0, 0.0]);
    assert_eq!(tool(Tcp::FLANGE, 0.0, [0.0; 3], None), Ok(Tool::NONE));
}

#[test]
fn each_bad_value_is_named_with_what_is_allowed() {
    let nan_com = tool(Tcp::FLANGE, 1.0, [0.0, f64::NAN, 0.0], None).unwrap_err();
    assert_eq!(nan_com.field().to_string(), "center_of_mass[1]");
    assert!(
        nan_com.to_string().contains("expected a finite number"),
        "{nan_com}"
    );

    let heavy = tool(Tcp::FLANGE, 5.5, [0.0; 3], None).unwrap_err();
    assert_eq!(heavy, ToolError::Mass { value: 5.5 });
    assert!(heavy.to_string().contains("from 0 to 5 kg"), "{heavy}");
    assert_eq!(heavy.bounds(), (0.0, MAX_MASS_KG));
    assert!(tool(Tcp::FLANGE, -0.1, [0.0; 3], None).is_err());

    let skewed = Tcp {
        position: [0.0; 3],
        orientation: [0.0, 0.0, 0.0, 1.01],
    };
    let e = tool(skewed, 1.0, [0.0; 3], None).unwrap_err();
    assert_eq!(e.field().to_string(), "tcp.orientation");
    assert!(e.to_string().contains("norm 1.01"), "{e}");

    let long = Tcp {
        position: [0.0, 0.4, 0.4],
        orientation: [0.0, 0.0, 0.0, 1.0],
    };
    let e = tool(long, 1.0, [0.0; 3], None).unwrap_err();
    assert_eq!(e.field().to_string(), "tcp.position");
    assert!(e.to_string().contains("at most 0.5 m"), "{e}");
    let e = tool(Tcp::FLANGE, 1.0, [0.6, 0.0, 0.0], None).unwrap_err();
    assert_eq!(e.field().to_string(), "center_of_mass");
}

#[test]
fn only_the_inertia_of_a_body_is_accepted() {
    let ok = |i: [f64; 6]| tool(Tcp::FLANGE, 1.0, [0.0; 3], Some(i));
    // A thin rod along z: izz = 0, ixx = iyy (the triangle inequality's edge).
    assert!(ok([0.02, 0.02, 0.0, 0.0, 0.0, 0.0]).is_ok());
    // A rotated box: products of inertia within the positive semi-definite range.
    assert!(ok([0.02, 0.03, 0.04, 0.005, -0.002, 0.001]).is_ok());
    // Negative moment.
    assert!(matches!(
        ok([-0.01, 0.02, 0.02, 0.0, 0.0, 0.0]),
        Err(ToolError::Inertia { .. })
    ));
    // Triangle inequality broken: izz > ixx + iyy.
    assert!(matches!(
        ok([0.01, 0.01, 0.03, 0.0, 0.0, 0.0]),
        Err(ToolError::Inertia { .. })
    ));
    // Positive diagonal, but a product of inertia too large (not positive semi-definite).
    let e = ok([0.02, 0.02, 0.02, 0.03, 0.0, 0.0]).unwrap_err();
    assert!(e.to_string().contains("positive semi-definite"), "{e}");
}
