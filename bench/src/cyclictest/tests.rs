use super::*;

const SAMPLE: &str = "# /dev/cpu_dma_latency set to 0us
# Histogram
000000 000000
000001 000000
000002 000003
000003 000090
000004 000006
000005 000000
# Total: 000000100
# Min Latencies: 00002
# Avg Latencies: 00003
# Max Latencies: 00031
# Histogram Overflows: 00001
# Histogram Overflow at cycle number:
# Thread 0: 00042
";

#[test]
fn parses_histogram_and_summary_lines() {
    let r = parse(SAMPLE).unwrap();
    assert_eq!(r.buckets, vec![0, 0, 3, 90, 6, 0]);
    assert_eq!(r.total, 100);
    assert_eq!(r.max_us, 31);
    assert_eq!(r.overflows, 1);
    assert_eq!(r.percentile(50.0), Some(HistFigure::Us(3)));
    assert_eq!(r.percentile(99.0), Some(HistFigure::Us(4)));
    assert_eq!(r.percentile(99.9), Some(HistFigure::Beyond { limit: 6 }));
}

#[test]
fn refuses_output_without_the_summary() {
    let cut: String = SAMPLE.lines().take(8).collect::<Vec<_>>().join("\n");
    let e = parse(&cut).unwrap_err().to_string();
    assert!(e.contains("no `# Total:` line"), "{e}");
    assert!(parse("").is_err());
}
