use super::*;

#[test]
fn duplicate_keys_are_refused_at_any_depth() {
    for (text, key) in [
        (r#"{"command":"nope","command":"status"}"#, "command"),
        (
            r#"{"command":"move_axis","arguments":{"axis_index":9,"axis_index":6}}"#,
            "axis_index",
        ),
        (r#"[1,{"a":[{"x":1,"y":2,"x":3}]}]"#, "x"),
        // The same key after an escape is the same key.
        (r#"{"k":1,"\u006b":2}"#, "k"),
    ] {
        assert_eq!(
            parse(text),
            Err(ParseError::DuplicateKey { key: key.into() }),
            "{text}"
        );
    }
    let e = parse(r#"{"a":1,"a":2}"#).unwrap_err().to_string();
    assert!(e.contains("duplicate key \"a\""), "{e}");
}

#[test]
fn same_key_in_different_objects_is_fine() {
    let v = parse(r#"{"a":{"a":1},"b":[{"a":2},{"a":3}]}"#).unwrap();
    assert_eq!(v["b"][1]["a"], 3);
}

#[test]
fn syntax_errors_and_trailing_text() {
    assert!(matches!(parse("{\"a\":"), Err(ParseError::Syntax(_))));
    assert!(matches!(parse("{} x"), Err(ParseError::Syntax(_))));
    assert_eq!(
        parse(" [1.5, -2, 3] ").unwrap(),
        serde_json::json!([1.5, -2, 3])
    );
}

#[test]
fn output_is_ascii_with_escapes() {
    let v = serde_json::json!({"s": "a\u{e9}\u{1F600}\n\"", "k\u{e4}": [1]});
    let compact = to_ascii(&v);
    assert_eq!(compact, r#"{"k\u00e4":[1],"s":"a\u00e9\ud83d\ude00\n\""}"#);
    assert_eq!(serde_json::from_str::<Value>(&compact).unwrap(), v);
    let pretty = to_ascii_pretty(&v);
    assert!(
        pretty.is_ascii() && pretty.contains("\n  \"s\""),
        "{pretty}"
    );
    assert_eq!(serde_json::from_str::<Value>(&pretty).unwrap(), v);
}
