//! Headless Chromium driven over the DevTools protocol (a WebSocket, via
//! tungstenite): open a page, evaluate JavaScript in it (read the DOM,
//! click buttons, fill forms), wait for a condition, take screenshots.
//! Enough to use a page as a person would, without a WebDriver.

use base64::Engine as _;
use serde_json::{json, Value};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use tungstenite::{stream::MaybeTlsStream, Message, WebSocket};

pub struct Browser {
    child: Child,
    socket: WebSocket<MaybeTlsStream<TcpStream>>,
    next_id: u64,
    _profile: tempfile::TempDir,
}

impl Browser {
    /// Chromium (installed from the distribution's packages when missing)
    /// showing `url` in a `width`×`height` window; `Err` says why not.
    pub fn open(url: &str, width: u32, height: u32) -> Result<Browser, String> {
        Browser::open_with(url, width, height, &[])
    }

    /// `open` with more command-line switches (`--host-resolver-rules=...`).
    pub fn open_with(url: &str, width: u32, height: u32, switches: &[&str]) -> Result<Browser, String> {
        super::tools::ensure("chromium", &["--version"], &["chromium"])?;
        let profile = tempfile::tempdir().map_err(|e| e.to_string())?;
        let mut child = Command::new("chromium")
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--hide-scrollbars",
                "--remote-debugging-port=0",
                &format!("--window-size={width},{height}"),
                &format!("--user-data-dir={}", profile.path().display()),
            ])
            .args(switches)
            .arg("about:blank")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| format!("chromium does not start: {e}"))?;
        let stderr = child.stderr.take().ok_or("no stderr")?;
        let mut lines = BufReader::new(stderr).lines();
        let endpoint = loop {
            let Some(Ok(line)) = lines.next() else {
                let _ = child.kill();
                return Err("chromium ended without a DevTools endpoint".into());
            };
            if let Some(at) = line.find("ws://") {
                break line[at..].trim().to_string();
            }
        };
        // Keep draining stderr so that chromium never blocks on it.
        std::thread::spawn(move || for _ in lines {});
        let port = endpoint
            .trim_start_matches("ws://")
            .split('/')
            .next()
            .ok_or("no DevTools address")?
            .to_string();
        let targets = http_get(&port, "/json/list")?;
        let targets: Value = serde_json::from_str(&targets).map_err(|e| e.to_string())?;
        let page = targets
            .as_array()
            .and_then(|list| list.iter().find(|t| t["type"] == "page"))
            .and_then(|t| t["webSocketDebuggerUrl"].as_str())
            .ok_or("no page target")?
            .to_string();
        let (socket, _) = tungstenite::connect(page.as_str()).map_err(|e| e.to_string())?;
        let mut browser = Browser {
            child,
            socket,
            next_id: 0,
            _profile: profile,
        };
        browser.call("Page.enable", json!({}))?;
        browser.call("Page.navigate", json!({ "url": url }))?;
        Ok(browser)
    }

    /// Sends a DevTools command and waits for its answer.
    pub fn call(&mut self, method: &str, params: Value) -> Result<Value, String> {
        self.next_id += 1;
        let id = self.next_id;
        let message = json!({ "id": id, "method": method, "params": params }).to_string();
        self.socket.send(Message::text(message)).map_err(|e| e.to_string())?;
        loop {
            let message = self.socket.read().map_err(|e| e.to_string())?;
            let Message::Text(text) = message else { continue };
            let value: Value = serde_json::from_str(text.as_str()).map_err(|e| e.to_string())?;
            if value["id"] == id {
                if let Some(error) = value.get("error") {
                    return Err(format!("{method}: {error}"));
                }
                return Ok(value["result"].clone());
            }
        }
    }

    /// The value of a JavaScript expression in the page (promises awaited).
    pub fn eval(&mut self, expression: &str) -> Value {
        let result = self.call(
            "Runtime.evaluate",
            json!({ "expression": expression, "returnByValue": true, "awaitPromise": true }),
        );
        match result {
            Ok(result) => result["result"]["value"].clone(),
            Err(error) => panic!("evaluating `{expression}`: {error}"),
        }
    }

    /// Waits until `expression` is true in the page; false after `timeout`.
    pub fn wait_for(&mut self, expression: &str, timeout: Duration) -> bool {
        let until = Instant::now() + timeout;
        while Instant::now() < until {
            if self.eval(&format!("Boolean({expression})")) == Value::Bool(true) {
                return true;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        false
    }

    /// A PNG of the window, written to `path`.
    pub fn screenshot(&mut self, path: &std::path::Path) {
        let shot = self
            .call("Page.captureScreenshot", json!({ "format": "png" }))
            .expect("a screenshot");
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(shot["data"].as_str().unwrap_or(""))
            .expect("base64 PNG");
        std::fs::write(path, bytes).expect("the screenshot is written");
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A GET on the DevTools HTTP endpoint.
fn http_get(address: &str, path: &str) -> Result<String, String> {
    let mut stream = TcpStream::connect(address).map_err(|e| e.to_string())?;
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .map_err(|e| e.to_string())?;
    write!(
        stream,
        "GET {path} HTTP/1.1\r\nHost: {address}\r\nConnection: close\r\n\r\n"
    )
    .map_err(|e| e.to_string())?;
    // Chromium keeps the connection open despite `Connection: close`:
    // reading to the end would wait for the read timeout (10 s per browser
    // started). The body is as long as its header says; the DevTools server
    // always says it.
    let mut reader = BufReader::new(stream);
    let mut status = String::new();
    reader.read_line(&mut status).map_err(|e| e.to_string())?;
    if status.split_whitespace().nth(1) != Some("200") {
        return Err(format!("DevTools answered {path} with `{}`", status.trim_end()));
    }
    let mut length = None;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).map_err(|e| e.to_string())? == 0 {
            return Err(format!("DevTools closed the answer to {path} within its headers"));
        }
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some((name, value)) = line.split_once(':') {
            if name.eq_ignore_ascii_case("content-length") {
                length = Some(
                    value
                        .trim()
                        .parse()
                        .map_err(|_| format!("a Content-Length of {value}"))?,
                );
            }
        }
    }
    let length = length.ok_or_else(|| format!("DevTools answered {path} without a Content-Length"))?;
    let mut body = vec![0; length];
    reader.read_exact(&mut body).map_err(|e| e.to_string())?;
    String::from_utf8(body).map_err(|e| e.to_string())
}
