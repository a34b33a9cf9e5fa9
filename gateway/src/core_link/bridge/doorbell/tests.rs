use super::*;
use crate::core_link::bridge::wait::{Readiness, wait_readable};
use std::time::Duration;

#[test]
fn a_ring_wakes_the_wait_until_cleared() {
    let bell = Doorbell::new().unwrap();
    let quiet = wait_readable(&[bell.fd()], Duration::from_millis(1)).unwrap();
    assert_eq!(quiet, Readiness::default());
    bell.ring();
    bell.ring();
    let rung = wait_readable(&[bell.fd()], Duration::from_secs(5)).unwrap();
    assert!(rung.ready[0]);
    bell.clear();
    let cleared = wait_readable(&[bell.fd()], Duration::from_millis(1)).unwrap();
    assert!(!cleared.ready[0]);
}
