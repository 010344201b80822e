//! Finding R1 of the outside test of 2026-11-27: the help lists every exit
//! status, 4 (model error) included, and each command whose verdict can end
//! with 3 or 4 (`identify`, `demo`, `merge`) says so in its own help.
use crate::support;

use support::*;

/// `rfeid ARGS… --help`'s standard output on one line.
fn help(args: &[&str]) -> String {
    let o = rfeid().args(args).arg("--help").output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{args:?}");
    flat(&o.stdout)
}

#[test]
fn every_help_that_can_end_with_3_or_4_lists_the_exit_statuses() {
    let top = help(&[]);
    assert!(
        top.contains("3 the identification's result was written but its verdict is suspect, 4 it was written and its verdict is model error"),
        "{top}"
    );
    for command in ["identify", "demo", "merge"] {
        let text = help(&[command]);
        for status in [
            "Exit status: 0 trustworthy",
            "3 written but suspect",
            "4 written but model error",
            "2 bad input",
            "docs/reference/exit-status.md",
        ] {
            assert!(text.contains(status), "{command}: no {status:?} in {text}");
        }
    }
}
