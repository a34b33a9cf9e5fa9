use super::*;
use std::collections::HashSet;

/// The numbers of the core's codes are the shared-memory contract: clients of other languages
/// and recorded flight-recorder files read them. They never change.
#[test]
fn the_wire_numbers_do_not_change() {
    let pinned = [
        (RejectCode::None, 0),
        (RejectCode::WrongMode, 1),
        (RejectCode::NotCalibrated, 2),
        (RejectCode::EmergencyStop, 3),
        (RejectCode::DriveDisconnected, 4),
        (RejectCode::DriveFault, 5),
        (RejectCode::OutOfRange, 6),
        (RejectCode::NotAvailable, 7),
        (RejectCode::NotSimulated, 8),
        (RejectCode::QueueFull, 9),
        (RejectCode::PositionLimit, 10),
        (RejectCode::VelocityLimit, 11),
        (RejectCode::BrakingDistance, 12),
        (RejectCode::FollowingError, 13),
        (RejectCode::CalibrationFailed, 14),
        (RejectCode::Aborted, 15),
        (RejectCode::Busy, 16),
        (RejectCode::PvtPoint, 17),
        (RejectCode::Unreachable, 18),
        (RejectCode::NotOwner, 19),
        (RejectCode::ShuttingDown, 20),
        (RejectCode::Overload, 21),
        (RejectCode::NotIdentifiable, 22),
    ];
    assert_eq!(
        RejectCode::ALL.len(),
        pinned.len(),
        "a code was added: pin it here"
    );
    for (code, number) in pinned {
        assert_eq!(code.to_wire(), number, "{code:?}");
    }
}

#[test]
fn names_are_unique_snake_case_and_read_back() {
    let mut seen = HashSet::new();
    for c in ErrorCode::ALL {
        let name = c.as_str();
        assert!(seen.insert(name), "{name} twice");
        assert!(
            !name.is_empty()
                && name
                    .chars()
                    .all(|ch| ch.is_ascii_lowercase() || ch.is_ascii_digit() || ch == '_'),
            "{name} is not snake_case"
        );
        assert_eq!(ErrorCode::from_name(name), Some(*c));
        assert!(!c.meaning().is_empty() && !c.remedy().is_empty(), "{name}");
        assert!(
            !c.meaning().contains('|') && !c.remedy().contains('|'),
            "{name}"
        );
    }
    assert_eq!(ErrorCode::from_name("none"), None, "`none` is no error");
}

#[test]
fn every_reject_code_but_none_is_an_error_code_of_the_same_name() {
    for r in RejectCode::ALL {
        match r.error_code() {
            None => assert_eq!(*r, RejectCode::None),
            Some(c) => {
                assert_eq!(c.as_str(), r.as_str());
                assert_eq!(c.reject_code(), Some(*r));
            }
        }
    }
    let core = ErrorCode::ALL.iter().filter(|c| c.reject_code().is_some());
    assert_eq!(core.count(), RejectCode::ALL.len() - 1);
}

const BEGIN: &str = "<!-- error codes: generated from shared/src/error_code.rs -->\n";
const END: &str = "<!-- end of the error codes -->";

/// `docs/protocol.md` lists every code as the table defines it;
/// `MCM_UPDATE_DOCS=1 cargo test -p mcm-shared --lib error_code` writes the list anew.
#[test]
fn the_protocol_document_lists_every_code() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/protocol.md");
    let doc = std::fs::read_to_string(&path).expect("docs/protocol.md");
    let (start, end) = match (doc.find(BEGIN), doc.find(END)) {
        (Some(s), Some(e)) if s < e => (s + BEGIN.len(), e),
        _ => panic!(
            "docs/protocol.md has no `{}` ... `{END}` section",
            BEGIN.trim()
        ),
    };
    let table = markdown_table();
    if doc[start..end] != table && std::env::var_os("MCM_UPDATE_DOCS").is_some() {
        let updated = format!("{}{table}{}", &doc[..start], &doc[end..]);
        std::fs::write(&path, updated).expect("write docs/protocol.md");
        return;
    }
    assert!(
        doc[start..end] == table,
        "docs/protocol.md's error codes differ from shared/src/error_code.rs; \
         `MCM_UPDATE_DOCS=1 cargo test -p mcm-shared --lib error_code` writes them anew"
    );
}
