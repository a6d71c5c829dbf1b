//! Loading and hot reload cost little whatever is dropped into a watched folder: a 50 MB file,
//! a 100,000-character line, a link loop, a byte-order mark.

use libero_behavior::files::MAX_FILE_BYTES;
use libero_behavior::testing::example_vocabulary;
use libero_behavior::{
    validate_paths, Library, LiveLibrary, NoDataFiles, ReloadEvent, ReloadOptions,
};
use libero_watch::DEFAULT_EVENT_CAPACITY;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

const TREE: &str = "Behaviors(trees: { \"Main\": Action(\"Stand\") })\n";
const FIFTY_MB: u64 = 50 << 20;

fn folder_with_a_tree() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let behaviors = dir.path().join("behaviors");
    std::fs::create_dir(&behaviors).unwrap();
    std::fs::write(behaviors.join("main.ron"), TREE).unwrap();
    (dir, behaviors)
}

/// A file of `size` bytes that costs nothing to make: sparse, all zero bytes (valid UTF-8,
/// so only the size check keeps it from being read and parsed).
fn sparse_file(path: &Path, size: u64) {
    std::fs::File::create(path).unwrap().set_len(size).unwrap();
}

fn wait_for_events(live: &LiveLibrary, count: u64) -> Duration {
    let start = Instant::now();
    while live.events().pushed() < count {
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "no reload event {count}"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    start.elapsed()
}

#[test]
fn a_50_mb_file_is_refused_at_once_with_a_short_report_and_events_stay_bounded() {
    let (_dir, behaviors) = folder_with_a_tree();
    let debounce = Duration::from_millis(30);
    let live = LiveLibrary::start(
        vec![behaviors.clone()],
        Arc::new(example_vocabulary()),
        Arc::new(NoDataFiles),
        ReloadOptions { debounce },
    )
    .unwrap_or_else(|report| panic!("{}", report.render_text()));
    let big = behaviors.join("big.ron");

    let start = Instant::now();
    sparse_file(&big, FIFTY_MB);
    wait_for_events(&live, 1);
    let refused_after = start.elapsed();
    let Some(ReloadEvent::Rejected { report }) = live.next_event(Duration::ZERO) else {
        panic!("the 50 MB file was not rejected");
    };
    let text = report.render_text();
    eprintln!(
        "refused after {refused_after:?}; report {} bytes:\n{text}",
        text.len()
    );
    assert!(refused_after < Duration::from_secs(1), "{refused_after:?}");
    assert!(text.len() < 2048, "{} bytes", text.len());
    assert!(
        text.contains("big.ron") && text.contains(&MAX_FILE_BYTES.to_string()),
        "{text}"
    );
    assert_eq!(live.generation(), 1, "the running version stays");

    // The same problem is not reported again while nothing changes.
    std::fs::write(behaviors.join("main.ron"), TREE).unwrap();
    std::thread::sleep(debounce * 8);
    assert_eq!(live.events().pushed(), 1, "reported twice");

    // Many more rejections than the queue holds, none taken: the queue stays at its capacity.
    let rejections = DEFAULT_EVENT_CAPACITY as u64 + 8;
    for i in 1..=rejections {
        sparse_file(&big, FIFTY_MB + i);
        let took = wait_for_events(&live, 1 + i);
        assert!(took < Duration::from_secs(1), "rejection {i} took {took:?}");
    }
    assert_eq!(live.events().len(), DEFAULT_EVENT_CAPACITY);
    assert_eq!(
        live.events().dropped(),
        rejections - DEFAULT_EVENT_CAPACITY as u64
    );

    std::fs::remove_file(&big).unwrap();
    wait_for_events(&live, 2 + rejections);
    assert_eq!(live.generation(), 2, "the fix goes live");
}

#[test]
fn a_100_000_character_line_is_reported_in_a_few_lines() {
    let name = "K".repeat(100_000);
    let text = format!("{name}(trees: {{}})");
    let report = match Library::from_texts(
        &[("behaviors/long.ron", &text)],
        &example_vocabulary(),
        &NoDataFiles,
    ) {
        Ok(_) => panic!("an unknown file kind was accepted"),
        Err(report) => report,
    };
    let rendered = report.render_text();
    assert!(
        rendered.len() < 2048,
        "{} bytes:\n{rendered}",
        rendered.len()
    );
    assert!(rendered.contains("unknown file kind `KKKK"), "{rendered}");
    assert!(rendered.contains('…'), "{rendered}");
    assert!(report.render_json().len() < 2048);
}

#[cfg(unix)]
#[test]
fn a_folder_of_link_loops_validates_at_once_and_defines_nothing_twice() {
    use std::os::unix::fs::symlink;
    let (_dir, behaviors) = folder_with_a_tree();
    symlink("b", behaviors.join("a")).unwrap();
    symlink("a", behaviors.join("b")).unwrap();
    symlink(".", behaviors.join("self")).unwrap();
    symlink("..", behaviors.join("up")).unwrap();
    let start = Instant::now();
    let report = validate_paths(
        std::slice::from_ref(&behaviors),
        &example_vocabulary(),
        &NoDataFiles,
    );
    let took = start.elapsed();
    let text = report.render_text();
    eprintln!("validated in {took:?}:\n{text}");
    assert!(took < Duration::from_secs(1), "{took:?}");
    assert!(!text.contains("defined twice"), "{text}");
    assert_eq!(report.error_count(), 0, "{text}");
    assert_eq!(report.warning_count(), 3, "{text}");
}

#[test]
fn a_file_with_a_byte_order_mark_loads() {
    let (_dir, behaviors) = folder_with_a_tree();
    std::fs::write(behaviors.join("main.ron"), format!("\u{feff}{TREE}")).unwrap();
    let library = Library::load(
        std::slice::from_ref(&behaviors),
        &example_vocabulary(),
        &NoDataFiles,
    )
    .unwrap_or_else(|report| panic!("{}", report.render_text()));
    assert!(library.tree("Main").is_some());
    let from_text = format!("\u{feff}{TREE}");
    assert!(Library::from_texts(
        &[("m.ron", &from_text)],
        &example_vocabulary(),
        &NoDataFiles
    )
    .is_ok());
}

#[test]
fn a_binary_file_is_an_error_naming_it() {
    let (_dir, behaviors) = folder_with_a_tree();
    std::fs::write(behaviors.join("blob.ron"), [0u8, 159, 146, 150, 255]).unwrap();
    let report = validate_paths(
        std::slice::from_ref(&behaviors),
        &example_vocabulary(),
        &NoDataFiles,
    );
    assert_eq!(report.error_count(), 1);
    assert!(report.render_text().contains("blob.ron is not UTF-8 text"));
}
