use super::*;
use futures_util::FutureExt;
use tokio::io::{AsyncBufReadExt, AsyncWriteExt, BufReader};

const HOLD: &[u8] = br#"{"command":"hold"}"#;

fn new_pipe() -> (PageIn, CommandReader, ResultWriter, PageOut) {
    pipe(Arc::new(RobotConfig::prob2_default()))
}

/// Every result the page gets, each as often as it is sent, until the connection ends.
async fn all_results(out: &mut PageOut) -> Vec<String> {
    let mut got = Vec::new();
    while let Some((line, times)) = out.next().await {
        got.extend(std::iter::repeat_n(line, times as usize));
    }
    got
}

/// A connection that runs each command it reads (yielding a few times, as a command in the
/// core takes time) and answers it with its number: `{"ran":N,"command":...}`; before the
/// result of each `hold`, a spontaneous safety error (it names a `check`).
async fn connection(reader: CommandReader, mut writer: ResultWriter) -> usize {
    let mut lines = BufReader::new(reader).lines();
    let mut ran = 0;
    while let Some(line) = lines.next_line().await.unwrap() {
        for _ in 0..5 {
            tokio::task::yield_now().await;
        }
        if line.contains("hold") {
            writer
                .write_all(b"{\"check\":\"following_error\"}\n")
                .await
                .unwrap();
        }
        let cmd: Value = serde_json::from_str(&line).unwrap();
        let result = serde_json::json!({"ran": ran, "command": cmd["command"]});
        writer
            .write_all(format!("{result}\n").as_bytes())
            .await
            .unwrap();
        ran += 1;
    }
    ran
}

#[tokio::test]
async fn a_flood_of_holds_runs_few_and_each_gets_its_answer() {
    const SENT: usize = 100_000;
    let (page_in, reader, writer, mut page_out) = new_pipe();
    let conn = tokio::spawn(connection(reader, writer));
    let results = tokio::spawn(async move { all_results(&mut page_out).await });
    for i in 0..SENT {
        page_in.send(HOLD.to_vec()).await.unwrap();
        if i % 1000 == 0 {
            tokio::task::yield_now().await;
        }
    }
    page_in
        .send(br#"{"command":"status"}"#.to_vec())
        .await
        .unwrap();
    drop(page_in);
    let ran = conn.await.unwrap();
    let got = results.await.unwrap();

    assert!((2..SENT / 100).contains(&ran), "{ran} of {SENT} holds ran");
    let answers: Vec<Value> = got
        .iter()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .filter(|v| v.get("check").is_none())
        .collect();
    assert_eq!(answers.len(), SENT + 1, "one answer per command");
    assert!(answers[..SENT].iter().all(|v| v["command"] == "hold"));
    assert_eq!(answers[SENT]["command"], "status");
    assert_eq!(answers[SENT]["ran"], ran - 1);
    // In the order the holds ran, each safety error sent once.
    let order: Vec<u64> = answers.iter().map(|v| v["ran"].as_u64().unwrap()).collect();
    assert!(order.windows(2).all(|w| w[0] <= w[1]), "answers in order");
    assert_eq!(got.len() - answers.len(), ran - 1, "each interjection once");
}

#[tokio::test]
async fn a_hold_that_arrives_while_one_runs_runs_after_it() {
    let (page_in, reader, _writer, _out) = new_pipe();
    let mut lines = BufReader::new(reader).lines();
    page_in.send(HOLD.to_vec()).await.unwrap();
    // Taken: it runs now.
    assert_eq!(lines.next_line().await.unwrap().unwrap().as_bytes(), HOLD);
    page_in.send(HOLD.to_vec()).await.unwrap();
    page_in.send(HOLD.to_vec()).await.unwrap();
    // Another spelling of `hold` is another message; then one more `hold` is not joined to
    // the one before it.
    page_in
        .send(br#"{"command": "hold"}"#.to_vec())
        .await
        .unwrap();
    page_in.send(HOLD.to_vec()).await.unwrap();
    drop(page_in);
    let mut rest = Vec::new();
    while let Some(l) = lines.next_line().await.unwrap() {
        rest.push(l);
    }
    assert_eq!(
        rest,
        [
            r#"{"command":"hold"}"#,
            r#"{"command": "hold"}"#,
            r#"{"command":"hold"}"#
        ]
    );
}

#[tokio::test]
async fn other_commands_wait_for_room_and_are_never_joined() {
    let (page_in, reader, _writer, _out) = new_pipe();
    let big = format!(
        "{{\"command\":\"status\",\"pad\":\"{}\"}}",
        "x".repeat(PIPE_BYTES / 3)
    );
    let mut sent = 0;
    while page_in
        .send(big.clone().into_bytes())
        .now_or_never()
        .is_some()
    {
        sent += 1;
        assert!(sent < 10, "the pipe holds {PIPE_BYTES} bytes");
    }
    assert_eq!(sent, 2, "a third would pass {PIPE_BYTES} bytes");
    let mut lines = BufReader::new(reader).lines();
    assert_eq!(lines.next_line().await.unwrap().unwrap(), big);
    assert!(page_in.send(big.into_bytes()).now_or_never().is_some());
    // The same message twice is two commands unless it is a `hold`.
    let (page_in, reader, _writer, _out) = new_pipe();
    for _ in 0..3 {
        page_in
            .send(br#"{"command":"status"}"#.to_vec())
            .await
            .unwrap();
    }
    drop(page_in);
    let mut lines = BufReader::new(reader).lines();
    let mut n = 0;
    while lines.next_line().await.unwrap().is_some() {
        n += 1;
    }
    assert_eq!(n, 3);
}

#[tokio::test]
async fn each_end_is_told_when_the_other_is_gone() {
    let (page_in, reader, mut writer, page_out) = new_pipe();
    drop(reader);
    assert_eq!(page_in.send(HOLD.to_vec()).await, Err(Closed));
    drop(page_out);
    assert!(writer.write_all(b"{}\n").await.is_err());
}
