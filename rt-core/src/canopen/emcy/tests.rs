use super::*;

#[test]
fn decodes_the_profile_emcys() {
    let f = Frame::new(0x085, &[0x41, 0x54, 0x05, 0, 0, 0, 0, 0]).unwrap();
    let e = Emcy::decode(&f, 4).unwrap();
    assert_eq!((e.node, e.axis, e.code, e.register), (5, 4, 0x5441, 0x05));
    assert_eq!(
        e.to_string(),
        "EMCY from node 5 (axis 5): code 0x5441 safe torque off active (emergency stop) \
         (class: device hardware), error register 0x05 [generic, voltage]"
    );
    assert_eq!(e.encode(), f);

    let reset = Emcy::decode(&Frame::new(0x081, &[0; 8]).unwrap(), 0).unwrap();
    assert!(reset.is_reset());
    assert_eq!(
        reset.to_string(),
        "EMCY from node 1 (axis 1): code 0x0000 error reset / no error (class: no error), \
         error register 0x00 [none]"
    );
}

#[test]
fn unknown_codes_fall_back_to_their_class_and_vendor_bytes_are_shown() {
    let f = Frame::new(0x082, &[0x34, 0x23, 0x03, 1, 2, 3, 4, 5]).unwrap();
    let e = Emcy::decode(&f, 1).unwrap();
    assert_eq!(e.code_text(), "current");
    assert!(
        e.to_string()
            .ends_with("error register 0x03 [generic, current], vendor data 0102030405"),
        "{e}"
    );
    assert_eq!(class_text(0x8611), "monitoring (CiA 402)");
    assert_eq!(class_text(0x8250), "protocol error");
    assert_eq!(class_text(0xFF01), "device specific");
    assert_eq!(code_text(0x8611), "following error");
}

#[test]
fn short_frames_are_refused() {
    let err = Emcy::decode(&Frame::new(0x083, &[0x30, 0x81]).unwrap(), 2).unwrap_err();
    assert_eq!(
        err.to_string(),
        "EMCY from COB-ID 0x083 has 2 data bytes; CiA 301 requires 8"
    );
}
