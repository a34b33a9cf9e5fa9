use super::*;

fn obs(cycle: u64, level: Option<usize>) -> Observation {
    Observation { cycle, level }
}

#[test]
fn classifies_levels_within_the_tolerance() {
    assert_eq!(classify(0.2), Some(0));
    assert_eq!(classify(-0.25), Some(1));
    assert_eq!(classify(0.43), Some(2));
    assert_eq!(classify(-0.4), Some(3));
    assert_eq!(classify(0.0), None);
    assert_eq!(classify(0.3), None);
    assert_eq!(level_of(0), 0);
    assert_eq!(level_of(5), 1);
    assert_eq!(level_of(7), 3);
}

#[test]
fn on_time_late_never_and_unobserved() {
    // Answers to cycles 10..=13 carry levels 0..=3.
    let answers: Vec<Answer> = (0..4)
        .map(|k| Answer {
            cycle: 10 + k,
            level: level_of(k),
        })
        .collect();
    let observations = [
        obs(11, Some(0)), // answer 0 on time
        obs(12, Some(0)), // answer 1 not yet in force...
        obs(13, Some(1)), // ...it came one cycle late
        // no state of cycle 14: answer 3 cannot be told
        obs(15, Some(3)),
    ];
    let t = tally(&observations, &answers);
    assert_eq!(t.answers, 4);
    assert_eq!(t.next_cycle, 1);
    assert_eq!(t.late, 1, "answer 1 seen in cycle 13");
    // Answer 2 (level 2, cycle 12): cycle 13 shows level 1, 14 unseen, 15 shows 3.
    assert_eq!(t.never, 1);
    assert_eq!(t.unobserved, 1);
    assert_eq!(t.on_time_share(), 0.25);
}

#[test]
fn an_answer_one_cycle_late_is_never_on_time() {
    // Every answer lands one cycle late: each next state shows the previous level.
    let answers: Vec<Answer> = (0..100)
        .map(|k| Answer {
            cycle: k,
            level: level_of(k),
        })
        .collect();
    let observations: Vec<Observation> = (1..=101)
        .map(|c| obs(c, (c >= 2).then(|| level_of(c - 2))))
        .collect();
    let t = tally(&observations, &answers);
    assert_eq!(t.next_cycle, 0);
    assert_eq!(t.late, 100);
    assert_eq!(t.on_time_share(), 0.0);
    assert_eq!(Tally::default().on_time_share(), 0.0);
}

#[test]
fn cycle_numbers_follow_the_periods_between_times() {
    let p = 0.005;
    let times = [10.0, 10.005, 10.0101, 10.0199, 10.0352];
    assert_eq!(cycle_numbers(&times, p), vec![0, 1, 2, 4, 7]);
    assert_eq!(cycle_numbers(&[], p), Vec::<u64>::new());
}
