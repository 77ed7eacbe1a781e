//! GX Developer projects served: their device comments in the monitor's
//! table, and `--watch-file` on a project (a broken save reported, the new
//! program keeping the project's steps).

use crate::common::server::{http, json, Server};
use std::process::Command;
use std::time::Duration;

#[test]
fn a_projects_device_comments_reach_the_monitor_table() {
    // The GX Developer sample's listing, as `ladderc import` writes it.
    let dir = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../testsuite/gxdeveloper/3floor_elevator"
    ));
    let listing = ladder_front::gxdev::read(&ladder_front::gxdev::locate(dir).unwrap()).unwrap();
    let server = Server::start_program(&listing, &["--http", "127.0.0.1:0"]);
    let web = server.web.unwrap();
    let (status, body) = http(web, "GET", "/api/devices?watch=Y10,X0,D0", "");
    assert_eq!(status, 200, "{body}");
    let value = json(&body);
    assert!(value["comments"]["Y10"].as_str().unwrap().contains("UP"), "{body}");
    assert!(value["comments"]["X0"].is_string(), "{body}");
    assert!(value["comments"].get("D0").is_none(), "D0 has no comment: {body}");
    let (_, page) = http(web, "GET", "/", "");
    assert!(page.contains("<th>comment</th>"));
}

#[test]
fn a_watched_project_reports_a_broken_save_and_keeps_its_steps() {
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("project");
    let import = |text: &str| {
        let program = dir.path().join("p.il");
        std::fs::write(&program, text).unwrap();
        let output = Command::new(env!("CARGO_BIN_EXE_ladderc"))
            .args(["import", program.to_str().unwrap(), "--to-gx-developer"])
            .arg(&project)
            .output()
            .unwrap();
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    };
    import("LD M8000\nMOV K1 D9\nEND\n");
    let server = Server::start_path(
        dir,
        &project,
        &["--http", "127.0.0.1:0", "--watch-file", "--watch-settle-ms", "200"],
    );
    let web = server.web.unwrap();
    let main = project.join("Pou/Body/MAIN.wpg");
    std::thread::sleep(Duration::from_millis(300));
    // A save cut short: reported, and the running program goes on.
    let whole = std::fs::read(&main).unwrap();
    std::fs::write(&main, &whole[..whole.len() - 1]).unwrap();
    std::thread::sleep(Duration::from_millis(1000));
    // The third instruction is at step 6 of the project (line 3 of the IL,
    // a later line of the listing).
    let program = server.dir.path().join("p.il");
    std::fs::write(&program, "LD M8000\nMOV K9000 Z0\nMOV K2 D0Z0\nEND\n").unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_ladderc"))
        .args(["import", program.to_str().unwrap(), "--to-gx-developer"])
        .arg(&project)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let mut value = serde_json::Value::Null;
    for _ in 0..50 {
        std::thread::sleep(Duration::from_millis(100));
        value = json(&http(web, "GET", "/api/devices?watch=D8069", "").1);
        if value["devices"]["D8069"] != 0 {
            break;
        }
    }
    assert_eq!(value["devices"]["D8069"], 6, "D8069 records the step: {value}");
    let (code, stderr) = server.stop();
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stderr.contains("E0053"), "{stderr}");
    assert!(
        stderr.contains("does not compile; the running program goes on"),
        "{stderr}"
    );
}
