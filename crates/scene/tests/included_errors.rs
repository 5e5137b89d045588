//! An error in an included file names the file and line, and the
//! `<include>` (file and line) that brought it in, through every level.

use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

#[test]
fn an_error_in_an_included_file_names_the_including_file_and_line() {
    let dir = std::env::temp_dir().join(format!("scotopia-incl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("main.xml"),
        "<scene version=\"3.0.0\">\n    <include filename=\"middle.xml\"/>\n</scene>\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("middle.xml"),
        "<scene version=\"3.0.0\">\n\n    <include filename=\"shape.xml\"/>\n</scene>\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("shape.xml"),
        "<scene version=\"3.0.0\">\n    <shape type=\"sphere\">\n        <float name=\"radius\" value=\"abc\"/>\n    </shape>\n</scene>\n",
    )
    .unwrap();
    let e = load_scene(&dir.join("main.xml"), &Parameters::new())
        .unwrap_err()
        .to_string();
    assert!(e.contains("shape.xml:3:9"), "{e}");
    assert!(
        e.contains("(included from ")
            && e.contains("middle.xml:3:5, included from ")
            && e.contains("main.xml:2:5)"),
        "{e}"
    );
    // The file given to load_scene names no include site.
    std::fs::write(
        dir.join("main.xml"),
        "<scene version=\"3.0.0\">\n    <shape type=\"sphere\"><float name=\"radius\" value=\"abc\"/></shape>\n</scene>\n",
    )
    .unwrap();
    let e = load_scene(&dir.join("main.xml"), &Parameters::new())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("main.xml:2:") && !e.contains("included from"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
