use super::*;

#[test]
fn codes_match_cia301() {
    let i = 0x1600;
    let cases = [
        (SdoAbort::ObjectDoesNotExist { index: i }, 0x0602_0000),
        (
            SdoAbort::SubIndexDoesNotExist { index: i, sub: 9 },
            0x0609_0011,
        ),
        (SdoAbort::WriteToReadOnly { index: i, sub: 0 }, 0x0601_0002),
        (SdoAbort::ReadOfWriteOnly { index: i, sub: 0 }, 0x0601_0001),
        (
            SdoAbort::LengthMismatch {
                index: i,
                sub: 0,
                expected: 1,
                given: 4,
            },
            0x0607_0010,
        ),
        (SdoAbort::DeviceState { index: i, sub: 1 }, 0x0800_0022),
        (
            SdoAbort::NotMappable {
                index: i,
                sub: 1,
                entry: 0x10000020,
            },
            0x0604_0041,
        ),
        (
            SdoAbort::MappingTooLong {
                index: i,
                count: 3,
                bits: 72,
            },
            0x0604_0042,
        ),
        (
            SdoAbort::ValueRange {
                index: i,
                sub: 0,
                value: 9,
                allowed: "0..=8",
            },
            0x0609_0030,
        ),
        (SdoAbort::InvalidCommand { command: 0xE0 }, 0x0504_0001),
    ];
    for (abort, code) in cases {
        assert_eq!(abort.code(), code, "{abort}");
    }
}

#[test]
fn messages_name_object_and_value() {
    let a = SdoAbort::ValueRange {
        index: 0x6060,
        sub: 0,
        value: 3,
        allowed: "0, 8 or 10",
    };
    assert_eq!(
        a.to_string(),
        "value 3 (0x3) written to 0x6060:0 is out of range; allowed 0, 8 or 10"
    );
}
