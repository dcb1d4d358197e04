//! The index of results/: `penumbra report --index results` writes every folder with its README's
//! title into results/README.md, and the committed README holds that index exactly, so a folder
//! missing from it fails here; the command on a small tree writes between its markers and refuses
//! what it cannot do in one line, writing nothing. And scripts/same-v.sh has a setting for every
//! method the binary lists. No GPU: nothing is rendered.

mod common;
use common::{penumbra, root, temp_dir};
use penumbra_lab::report::results_index::{splice, table, BEGIN, END};

#[test]
fn results_readme_lists_every_folder_with_its_title() {
    let results = root().join("results");
    let path = results.join("README.md");
    let readme = std::fs::read_to_string(&path).unwrap();
    let index = table(&results).unwrap();
    assert_eq!(
        splice(&readme, &index, &path).unwrap(),
        readme,
        "results/README.md's index is not the folders': run `penumbra report --index results`"
    );
    let folders: Vec<String> = std::fs::read_dir(&results)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert!(folders.len() >= 80, "{} folders", folders.len());
    for f in &folders {
        assert!(
            readme.contains(&format!("| `{f}/` | ")),
            "{f} is not in results/README.md"
        );
    }
    // A folder's title, less its own name: budget-promise's README opens `# budget-promise: …`.
    assert!(
        readme.contains(
            "| `budget-promise/` | `auto:target=T` against the oracle at three targets |"
        ),
        "{index}"
    );
}

#[test]
fn the_index_command_writes_between_its_markers_and_refuses_in_one_line() {
    let dir = temp_dir("results_index");
    let results = dir.join("results");
    for (name, title) in [
        ("b-two", "# b-two: the second | a pipe"),
        ("a-one", "# The first\n\nrows"),
    ] {
        std::fs::create_dir_all(results.join(name)).unwrap();
        std::fs::write(results.join(name).join("README.md"), title).unwrap();
    }
    let readme = results.join("README.md");
    std::fs::write(
        &readme,
        format!("# Results\n\nprose\n\n{BEGIN}\nstale\n{END}\nafter\n"),
    )
    .unwrap();
    let run = penumbra(&["report", "--index", results.to_str().unwrap()]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(&readme).unwrap(),
        format!("# Results\n\nprose\n\n{BEGIN}\n| folder | what |\n|---|---|\n| `a-one/` | The first |\n| `b-two/` | the second \\| a pipe |\n{END}\nafter\n")
    );
    // Without its markers, a folder without a README, two paths: one line, nothing written.
    let refused = |args: &[&str]| {
        let run = penumbra(args);
        assert_eq!(run.status.code(), Some(1));
        let stderr = String::from_utf8_lossy(&run.stderr).to_string();
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        stderr
    };
    std::fs::write(&readme, "# Results\n").unwrap();
    assert!(
        refused(&["report", "--index", results.to_str().unwrap()])
            .contains("README.md: no line <!-- index"),
        "no markers"
    );
    assert_eq!(std::fs::read_to_string(&readme).unwrap(), "# Results\n");
    std::fs::write(&readme, format!("{BEGIN}\n{END}\n")).unwrap();
    std::fs::create_dir_all(results.join("c-bare")).unwrap();
    assert!(refused(&["report", "--index", results.to_str().unwrap()])
        .contains("c-bare/README.md: a results folder needs its README.md"));
    assert_eq!(
        std::fs::read_to_string(&readme).unwrap(),
        format!("{BEGIN}\n{END}\n")
    );
    assert!(refused(&["report", "--index", "a", "b"]).contains("--index: takes one folder"));
}

#[test]
fn same_v_has_a_setting_for_every_method() {
    let run = std::process::Command::new("bash")
        .arg(root().join("scripts/same-v.sh"))
        .arg("--coverage")
        .arg(env!("CARGO_BIN_EXE_penumbra"))
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(String::from_utf8_lossy(&run.stdout).contains("every method"));
}
