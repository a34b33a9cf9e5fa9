use super::Bounded;
use cdr_encoding::{from_bytes, to_vec};
use serde::{Deserialize, Serialize};

type Le = byteorder::LittleEndian;

/// A message as a peer sends it: a plain sequence, then a field after it.
#[derive(Serialize)]
struct Sent {
    values: Vec<f64>,
    after: u32,
}

#[derive(Deserialize)]
struct Read {
    values: Bounded<f64, 3>,
    after: u32,
}

fn read(values: Vec<f64>) -> Read {
    let bytes = to_vec::<_, Le>(&Sent { values, after: 7 }).expect("encodes");
    from_bytes::<Read, Le>(&bytes).expect("decodes").0
}

#[test]
fn up_to_the_limit_every_element_is_kept() {
    for n in 0..=3 {
        let values: Vec<f64> = (0..n).map(f64::from).collect();
        let r = read(values.clone());
        assert_eq!(&r.values[..], &values[..]);
        assert_eq!(r.values.len(), values.len());
        assert!(!r.values.oversize());
        assert_eq!(r.after, 7, "the field after the sequence reads");
    }
}

#[test]
fn over_the_limit_none_is_kept_and_the_length_is() {
    let r = read((0..100_000).map(f64::from).collect());
    assert_eq!(r.values.len(), 100_000);
    assert!(r.values.oversize());
    assert!(r.values.iter().next().is_none(), "no element kept");
    assert_eq!(r.after, 7, "the whole sequence was read past");
}

#[test]
fn it_encodes_as_the_sequence_it_holds() {
    let b: Bounded<f64, 3> = vec![1.0, 2.0].into();
    let plain = to_vec::<_, Le>(&vec![1.0f64, 2.0]).expect("encodes");
    assert_eq!(to_vec::<_, Le>(&b).expect("encodes"), plain);
}
