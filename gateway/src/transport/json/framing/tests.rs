use super::*;

fn frames(input: &[u8]) -> Vec<Frame> {
    let mut d = Decoder::new();
    d.extend(input);
    std::iter::from_fn(|| d.next_frame()).collect()
}

fn obj(s: &str) -> Frame {
    Frame::Object(s.to_string())
}

#[test]
fn newline_delimited() {
    assert_eq!(
        frames(b"{\"command\":\"status\"}\n{\"command\":\"hold\"}\n"),
        vec![
            obj("{\"command\":\"status\"}"),
            obj("{\"command\":\"hold\"}")
        ]
    );
}

#[test]
fn complete_object_without_newline_is_taken_at_once() {
    assert_eq!(
        frames(b"{\"command\":\"release\"}"),
        vec![obj("{\"command\":\"release\"}")]
    );
}

#[test]
fn crlf_and_whitespace_between_objects() {
    assert_eq!(
        frames(b"  {\"a\":1}\r\n\r\n\t{\"b\":[1,{\"c\":2}]} \r\n"),
        vec![obj("{\"a\":1}"), obj("{\"b\":[1,{\"c\":2}]}")]
    );
}

#[test]
fn braces_inside_strings_do_not_count() {
    assert_eq!(
        frames(b"{\"s\":\"}{\\\"\"}\n"),
        vec![obj("{\"s\":\"}{\\\"\"}")]
    );
}

#[test]
fn byte_by_byte_feeding() {
    let input = b"{\"command\":\"status\",\"arguments\":{\"detail\":true}}\n{\"x\":1}";
    let mut d = Decoder::new();
    let mut out = Vec::new();
    for b in input {
        d.extend(&[*b]);
        while let Some(f) = d.next_frame() {
            out.push(f);
        }
    }
    assert_eq!(
        out,
        vec![
            obj("{\"command\":\"status\",\"arguments\":{\"detail\":true}}"),
            obj("{\"x\":1}")
        ]
    );
}

#[test]
fn non_ascii_is_refused_and_decoding_resumes() {
    let f = frames("{\"command\":\"stätus\"}\n{\"command\":\"hold\"}\n".as_bytes());
    assert_eq!(f.len(), 2);
    let Frame::Invalid { reason } = &f[0] else {
        panic!("{f:?}")
    };
    assert!(reason.contains("non-ASCII byte 0xC3"), "{reason}");
    assert_eq!(f[1], obj("{\"command\":\"hold\"}"));
}

#[test]
fn invalid_json_lines() {
    let f = frames(b"hello\n[1,2]\n42\n{\"a\":\n{\"ok\":true}\n");
    assert_eq!(f.len(), 5, "{f:?}");
    let reasons: Vec<String> = f[..4]
        .iter()
        .map(|x| match x {
            Frame::Invalid { reason } => reason.clone(),
            other => panic!("{other:?}"),
        })
        .collect();
    assert!(reasons[0].starts_with("invalid JSON"), "{}", reasons[0]);
    assert!(reasons[1].contains("got a JSON array"), "{}", reasons[1]);
    assert!(reasons[2].contains("got a JSON number"), "{}", reasons[2]);
    assert!(
        reasons[3].starts_with("incomplete JSON object"),
        "{}",
        reasons[3]
    );
    assert_eq!(f[4], obj("{\"ok\":true}"));
}

#[test]
fn oversize_object_is_reported_once_and_memory_is_bounded() {
    let mut d = Decoder::new();
    d.extend(b"{\"command\":\"");
    let chunk = vec![b'a'; 8192];
    let mut got = Vec::new();
    for _ in 0..20 {
        d.extend(&chunk);
        while let Some(f) = d.next_frame() {
            got.push(f);
        }
        assert!(d.buffered() <= MAX_COMMAND_BYTES + chunk.len());
    }
    assert_eq!(got, vec![Frame::Oversize]);
}

/// `{"s":"aaa..."}` of exactly `len` bytes.
fn object_of(len: usize) -> Vec<u8> {
    let mut v = b"{\"s\":\"".to_vec();
    v.resize(len - 2, b'a');
    v.extend_from_slice(b"\"}");
    assert_eq!(v.len(), len);
    v
}

#[test]
fn the_limit_is_exact_for_objects() {
    let mut at_limit = object_of(MAX_COMMAND_BYTES);
    at_limit.extend_from_slice(b"\r\n{\"a\":1}\n");
    let f = frames(&at_limit);
    assert_eq!(f.len(), 2);
    assert!(matches!(&f[0], Frame::Object(s) if s.len() == MAX_COMMAND_BYTES));
    assert_eq!(f[1], obj("{\"a\":1}"));
    // One byte more is refused, even when the whole object arrives in one read.
    let mut over = object_of(MAX_COMMAND_BYTES + 1);
    over.extend_from_slice(b"\n{\"a\":1}\n");
    assert_eq!(frames(&over), vec![Frame::Oversize, obj("{\"a\":1}")]);
    // Byte by byte: refused when byte MAX + 1 arrives.
    let mut d = Decoder::new();
    let over = object_of(MAX_COMMAND_BYTES + 1);
    d.extend(&over[..MAX_COMMAND_BYTES]);
    assert_eq!(d.next_frame(), None);
    d.extend(&over[MAX_COMMAND_BYTES..]);
    assert_eq!(d.next_frame(), Some(Frame::Oversize));
}

#[test]
fn the_limit_is_exact_for_other_lines() {
    let mut at_limit = vec![b'x'; MAX_COMMAND_BYTES];
    at_limit.extend_from_slice(b"\n{\"a\":1}\n");
    let f = frames(&at_limit);
    assert!(
        matches!(&f[..], [Frame::Invalid { .. }, Frame::Object(_)]),
        "{} frames",
        f.len()
    );
    let mut over = vec![b'x'; MAX_COMMAND_BYTES + 1];
    over.extend_from_slice(b"\n{\"a\":1}\n");
    assert_eq!(frames(&over), vec![Frame::Oversize, obj("{\"a\":1}")]);
}

#[test]
fn oversize_garbage_line_without_newline() {
    let mut d = Decoder::new();
    d.extend(&vec![b'x'; MAX_COMMAND_BYTES + 1]);
    assert_eq!(d.next_frame(), Some(Frame::Oversize));
    d.extend(b"xx\n{\"a\":1}\n");
    assert_eq!(d.next_frame(), Some(obj("{\"a\":1}")));
}

/// Two reads: the first brings a whole object and the start of the next, the second its end
/// and a CR LF.
#[test]
fn an_object_is_taken_when_complete_and_the_next_waits_for_its_end() {
    let mut d = Decoder::new();
    d.extend(b"{\"command\":\"status\"}{\"command\":");
    assert_eq!(d.next_frame(), Some(obj("{\"command\":\"status\"}")));
    assert_eq!(
        d.next_frame(),
        None,
        "the second object is not complete yet"
    );
    d.extend(b"\"hold\"}\r\n");
    assert_eq!(d.next_frame(), Some(obj("{\"command\":\"hold\"}")));
    assert_eq!(d.next_frame(), None);
    assert_eq!(d.buffered(), 0, "the line end is consumed");
}

#[test]
fn an_http_first_line_is_one_http_frame_before_its_body() {
    let request = b"POST / HTTP/1.1\r\nHost: robot:18010\r\nContent-Type: text/plain\r\n\r\n\n{\"command\":\"calibrate\"}\n";
    assert_eq!(frames(request)[0], Frame::Http(HttpLine::Request));
    // A header first (a request line too long to frame is cut, the next line is a header).
    assert_eq!(
        frames(b"\r\nHost: robot\r\n{\"command\":\"release\"}\n")[0],
        Frame::Http(HttpLine::Header)
    );
}

#[test]
fn http_lines_after_the_first_frame_are_invalid_lines() {
    let got = frames(b"{\"command\":\"status\"}\nPOST / HTTP/1.1\r\nHost: robot\r\n");
    assert_eq!(got[0], obj("{\"command\":\"status\"}"));
    assert!(
        got[1..].iter().all(|f| matches!(f, Frame::Invalid { .. })),
        "{got:?}"
    );
    let got = frames(b"hello\nHost: robot\n");
    assert!(
        got.iter().all(|f| matches!(f, Frame::Invalid { .. })),
        "{got:?}"
    );
}
