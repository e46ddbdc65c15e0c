//! The thesis-statement readings of `docs/scripts/thesis_statements.py` (its `statements/`
//! package) against their unit tests, `docs/scripts/test_thesis_statements.py`: every row says
//! yes on a synthetic sweep that does what the thesis says and no with the one change its test
//! names, and each tolerance holds and fails where it should. Python's unittest runs them; this
//! test fails when any of them fails (python3 with pyarrow and duckdb: `.ci/run` installs them).

use std::path::Path;
use std::process::Command;

#[test]
fn statement_readings_pass_their_unit_tests() {
    let scripts = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scripts");
    let out = Command::new("python3")
        .args(["-B", "-m", "unittest", "test_thesis_statements"])
        .current_dir(&scripts)
        .output()
        .unwrap_or_else(|e| panic!("python3 is needed for this test: {e}"));
    assert!(
        out.status.success(),
        "python3 -m unittest test_thesis_statements (in {}; needs pyarrow and duckdb, which \
         .ci/run installs) failed:\n{}",
        scripts.display(),
        String::from_utf8_lossy(&out.stderr)
    );
}
