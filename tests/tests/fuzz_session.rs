//! The fuzz target of the core's input paths ([`ecat_emu::fuzz::session`]) on the stable
//! toolchain: the committed seeds, everything the coverage-guided fuzzer kept in its corpus,
//! and random byte strings. A panic here is a bug in the core (or a broken rule of the target).

use ecat_core::AlState;
use ecat_emu::fuzz::{seeds, session};
use proptest::prelude::*;
use std::path::PathBuf;

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus/session")
}

/// The seeds reach what they are for, and the committed seed files are [`seeds`]' output (so
/// the fuzzer in CI starts from them): the sessions end in OP, PREOP and BOOT.
#[test]
fn the_seeds_reach_op_preop_and_boot_and_are_committed() {
    let seeds = seeds();
    let reached: Vec<AlState> = seeds.iter().map(|s| session(s)).collect();
    assert_eq!(reached, [AlState::Op, AlState::PreOp, AlState::Boot]);
    for (i, seed) in seeds.iter().enumerate() {
        let file = corpus().join(format!("seed-{i}"));
        let committed = std::fs::read(&file).unwrap_or_default();
        assert_eq!(
            &committed,
            seed,
            "{} differs from seeds()[{i}]",
            file.display()
        );
    }
}

/// Every input the fuzzer kept (the corpus grows as CI's fuzzer finds new paths and files are
/// committed; a crash found once stays here as a regression).
#[test]
fn every_corpus_input_runs_clean() {
    let mut n = 0;
    for entry in std::fs::read_dir(corpus()).expect("fuzz/corpus/session") {
        // A fuzzer running meanwhile replaces files as it reduces them.
        let Ok(data) = entry.and_then(|e| std::fs::read(e.path())) else {
            continue;
        };
        session(&data);
        n += 1;
    }
    assert!(n >= 2, "the corpus holds at least the seeds");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// Random byte strings, and random steps after a seed's way into OP or PREOP.
    #[test]
    fn any_bytes(tail in proptest::collection::vec(any::<u8>(), 0..600), which in 0usize..4) {
        let mut data = seeds().get(which).cloned().unwrap_or_default();
        data.extend_from_slice(&tail);
        session(&data);
    }
}
