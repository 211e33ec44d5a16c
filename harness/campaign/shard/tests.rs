use super::*;
use std::collections::HashMap;

fn env(vars: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
    let map: HashMap<String, String> = vars
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    move |name| map.get(name).cloned()
}

#[test]
fn k_of_n_parses_from_0_and_refuses_what_is_not_a_shard() {
    assert_eq!("2/4".parse(), Ok(Shard { index: 2, count: 4 }));
    assert_eq!(" 0 / 1 ".parse(), Ok(Shard::WHOLE));
    for (text, message) in [
        (
            "4/4",
            "shard 4 of 4: K counts from 0, so it must be below N = 4",
        ),
        ("0/0", "shard count 0"),
        ("1", "expected K/N"),
        ("a/3", "expected K/N"),
        ("-1/3", "expected K/N"),
        ("1/3/5", "expected K/N"),
    ] {
        let e = text.parse::<Shard>().expect_err(text).to_string();
        assert!(
            e.contains(message) && e.starts_with("--shard"),
            "{text}: {e}"
        );
    }
}

#[test]
fn the_slices_are_disjoint_cover_the_work_list_and_are_even() {
    for count in 1..=7u64 {
        for len in [0u64, 1, 5, 23, 256] {
            let mut seen = vec![0; len as usize];
            for index in 0..count {
                let positions = Shard { index, count }.positions(len);
                assert!(positions.windows(2).all(|w| w[0] < w[1]), "ascending");
                let n = positions.len() as u64;
                assert!(
                    n == len / count || n == len / count + 1,
                    "{n} of {len} / {count}"
                );
                for i in positions {
                    seen[i as usize] += 1;
                }
            }
            assert!(seen.iter().all(|&n| n == 1), "{count} shards of {len}");
        }
    }
}

/// Plain round robin would give shard K of a power-of-two N only the
/// positions i = K mod N, and a sweep's grid (innermost: 8 speed-up sets,
/// the shadow shortcut the lowest bit) would split along its dimensions.
#[test]
fn the_slices_do_not_follow_the_grid() {
    for count in [2u64, 4, 8] {
        for index in 0..count {
            let positions = Shard { index, count }.positions(256);
            let residues: std::collections::BTreeSet<u64> =
                positions.iter().map(|i| i % count).collect();
            assert_eq!(
                residues.len() as u64,
                count,
                "shard {index}/{count}: {positions:?}"
            );
            // Both settings of the lowest bit, in about equal numbers.
            let odd = positions.iter().filter(|&&i| i % 2 == 1).count();
            let n = positions.len();
            assert!(
                odd * 4 >= n && odd * 4 <= 3 * n,
                "{index}/{count}: {odd} odd of {n}"
            );
        }
    }
}

#[test]
fn slurm_array_ids_are_shifted_by_the_array_minimum() {
    let shard = Shard::from_env(
        &env(&[
            ("SLURM_ARRAY_TASK_ID", "12"),
            ("SLURM_ARRAY_TASK_MIN", "10"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]),
        None,
    );
    assert_eq!(shard, Ok(Some(Shard { index: 2, count: 4 })));
    let without_min = Shard::from_env(
        &env(&[
            ("SLURM_ARRAY_TASK_ID", "3"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]),
        None,
    );
    assert_eq!(without_min, Ok(Some(Shard { index: 3, count: 4 })));
    assert_eq!(Shard::from_env(&env(&[]), None), Ok(None));
}

#[test]
fn a_kubernetes_index_takes_its_count_from_the_flag_or_the_environment() {
    let vars = env(&[("JOB_COMPLETION_INDEX", "1"), ("RTCOSIM_SHARD_COUNT", "3")]);
    assert_eq!(
        Shard::from_env(&vars, None),
        Ok(Some(Shard { index: 1, count: 3 }))
    );
    assert_eq!(
        Shard::from_env(&vars, Some(5)),
        Ok(Some(Shard { index: 1, count: 5 }))
    );
}

/// Variables of an environment, name and value.
type Vars<'a> = &'a [(&'a str, &'a str)];

#[test]
fn bad_or_conflicting_environments_are_refused_naming_the_variables() {
    let cases: [(Vars, Option<u64>, &str); 7] = [
        (
            &[("SLURM_ARRAY_TASK_ID", "0"), ("JOB_COMPLETION_INDEX", "0")],
            Some(2),
            "both SLURM_ARRAY_TASK_ID=0 and JOB_COMPLETION_INDEX=0",
        ),
        (
            &[("SLURM_ARRAY_TASK_ID", "1")],
            None,
            "SLURM_ARRAY_TASK_COUNT is not",
        ),
        (
            &[
                ("SLURM_ARRAY_TASK_ID", "x"),
                ("SLURM_ARRAY_TASK_COUNT", "2"),
            ],
            None,
            "SLURM_ARRAY_TASK_ID=\"x\"",
        ),
        (
            &[
                ("SLURM_ARRAY_TASK_ID", "4"),
                ("SLURM_ARRAY_TASK_COUNT", "2"),
                ("SLURM_ARRAY_TASK_STEP", "2"),
            ],
            None,
            "SLURM_ARRAY_TASK_STEP=2",
        ),
        (
            &[
                ("SLURM_ARRAY_TASK_ID", "3"),
                ("SLURM_ARRAY_TASK_MIN", "5"),
                ("SLURM_ARRAY_TASK_COUNT", "2"),
            ],
            None,
            "below SLURM_ARRAY_TASK_MIN=5",
        ),
        (
            &[
                ("SLURM_ARRAY_TASK_ID", "7"),
                ("SLURM_ARRAY_TASK_COUNT", "4"),
            ],
            None,
            "shard 7 of 4",
        ),
        (
            &[("JOB_COMPLETION_INDEX", "0")],
            None,
            "--shard-count N or RTCOSIM_SHARD_COUNT",
        ),
    ];
    for (vars, count, message) in cases {
        let e = Shard::from_env(&env(vars), count).expect_err(message);
        assert!(e.to_string().contains(message), "{vars:?}: {e}");
    }
}

#[test]
fn the_flag_wins_over_the_environment_and_must_agree_with_the_count() {
    let flag = Some(Shard { index: 1, count: 2 });
    assert_eq!(Shard::resolve(flag, None), Ok(flag));
    let e = Shard::resolve(flag, Some(3)).expect_err("disagreeing counts");
    assert!(
        e.to_string().contains("--shard 1/2 and --shard-count 3"),
        "{e}"
    );
}
