//! A configuration that asks for the simulator in a build without it is refused, naming the
//! feature: the refusal itself in every build, and `run` refusing it in the build without the
//! `sim` feature (compiled in every test run by `tests/builds.rs`).

use super::*;

#[test]
fn the_simulated_backend_is_refused_unless_the_simulator_is_built_in() {
    let err = require_simulator(false).unwrap_err();
    assert!(matches!(err, RunError::SimNotBuilt), "{err}");
    assert!(err.to_string().contains("the `sim` feature"), "{err}");
    assert!(require_simulator(true).is_ok());
}

#[cfg(not(feature = "sim"))]
#[test]
fn without_the_sim_feature_the_simulated_backend_is_a_typed_error() {
    let opts = RunOptions {
        config: RobotConfig::prob2_default(),
        names: ServiceNames::new(&format!("nosim-{}", std::process::id())).unwrap(),
        allow_non_realtime: true,
        candump: None,
    };
    assert_eq!(opts.config.bus.backend, BusBackend::Sim);
    let err = run(opts, |_: &RtReport| panic!("started")).unwrap_err();
    assert!(matches!(err, RunError::SimNotBuilt), "{err}");
    assert!(err.to_string().contains("the `sim` feature"), "{err}");
}
