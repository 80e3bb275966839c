//! `print` writes byte for byte what the article's own program printed (tests/oracle/print).

use crate::common;
use common::*;

#[test]
fn print_matches_the_article_for_every_oracle_file() {
    let expected_files = files_in(&oracle("print"), "txt");
    for expected_path in expected_files {
        let name = expected_path.file_stem().unwrap().to_str().unwrap();
        let mut input = oracle("inputs").join(format!("{name}.bvh"));
        if !input.exists() {
            input = data(&format!("bvh/{name}.bvh"));
        }
        let output = crate::common::bvhview_command()
            .arg("print")
            .arg(&input)
            .output()
            .unwrap();
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let expected = std::fs::read(&expected_path).unwrap();
        assert!(
            output.stdout == expected,
            "{name}: print differs from the article's"
        );
    }
}
