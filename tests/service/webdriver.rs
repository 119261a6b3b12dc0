//! A small W3C WebDriver client over HTTP (the protocol is JSON over HTTP,
//! so reqwest is all it takes) driving headless Chromium through
//! ChromeDriver (Debian's `chromium` and `chromium-driver`; `.ci/run`
//! installs them).

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// The W3C element key in WebDriver answers.
const ELEMENT: &str = "element-6066-11e4-a52e-4f735466cecf";

/// How long `wait_*` polls before failing: a generous bound for a slow,
/// shared machine, not a timing claim.
pub const PATIENCE: Duration = Duration::from_secs(60);

/// A ChromeDriver process on a free port.
pub struct Driver {
    child: Child,
    base: String,
}

impl Driver {
    pub fn start() -> Driver {
        let binary = [
            "chromedriver",
            "/usr/bin/chromedriver",
            "/usr/lib/chromium/chromedriver",
        ]
        .into_iter()
        .find(|b| Command::new(b).arg("--version").output().is_ok())
        .expect(
            "chromedriver is installed (Debian package chromium-driver; `.ci/run` installs it)",
        );
        let mut child = Command::new(binary)
            .arg("--port=0")
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts");
        let stdout = BufReader::new(child.stdout.take().unwrap());
        let mut port = None;
        for line in stdout.lines() {
            let line = line.unwrap();
            if let Some(rest) = line.split("started successfully on port ").nth(1) {
                port = Some(rest.trim_end_matches('.').trim().to_string());
                break;
            }
        }
        let port = port.expect("chromedriver prints its port");
        Driver {
            child,
            base: format!("http://127.0.0.1:{port}"),
        }
    }

    /// A headless Chromium window of `width`×`height` CSS pixels that saves
    /// downloads in `downloads`.
    pub async fn session(&self, width: u32, height: u32, downloads: &Path) -> Session {
        let client = reqwest::Client::new();
        let profile = tempfile::tempdir().unwrap();
        let args = vec![
            "--headless=new".to_string(),
            "--no-sandbox".into(),
            "--disable-dev-shm-usage".into(),
            // WebGL in software: no GPU on a CI machine.
            "--use-angle=swiftshader".into(),
            "--enable-unsafe-swiftshader".into(),
            // The machine has no outside network: nothing may try it.
            "--disable-background-networking".into(),
            "--disable-component-update".into(),
            "--disable-sync".into(),
            "--no-first-run".into(),
            "--hide-scrollbars".into(),
            format!("--window-size={width},{height}"),
            format!("--user-data-dir={}", profile.path().display()),
        ];
        let binary = ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
            .into_iter()
            .find(|b| Path::new(b).exists());
        let mut options = json!({
            "args": args,
            "prefs": {
                "download.default_directory": downloads.display().to_string(),
                "download.prompt_for_download": false,
            },
        });
        if let Some(binary) = binary {
            options["binary"] = json!(binary);
        }
        let body = json!({"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": options,
        }}});
        let answer: Value = client
            .post(format!("{}/session", self.base))
            .json(&body)
            .send()
            .await
            .unwrap()
            .json()
            .await
            .unwrap();
        let id = answer["value"]["sessionId"]
            .as_str()
            .unwrap_or_else(|| panic!("no session: {answer}"))
            .to_string();
        let session = Session {
            base: format!("{}/session/{id}", self.base),
            client,
            _profile: profile,
        };
        session
            .command(
                "POST",
                "/chromium/send_command",
                json!({"cmd": "Page.setDownloadBehavior",
                       "params": {"behavior": "allow", "downloadPath": downloads.display().to_string()}}),
            )
            .await;
        session
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// One browser window.
pub struct Session {
    base: String,
    client: reqwest::Client,
    _profile: tempfile::TempDir,
}

impl Session {
    /// A WebDriver command; its `value`. Fails the test on a WebDriver error.
    pub async fn command(&self, method: &str, path: &str, body: Value) -> Value {
        self.try_command(method, path, body)
            .await
            .unwrap_or_else(|e| panic!("webdriver {method} {path}: {e}"))
    }

    async fn try_command(&self, method: &str, path: &str, body: Value) -> Result<Value, Value> {
        let url = format!("{}{path}", self.base);
        let request = match method {
            "GET" => self.client.get(url),
            "DELETE" => self.client.delete(url),
            _ => self.client.post(url).json(&body),
        };
        let response = request.send().await.unwrap();
        let ok = response.status().is_success();
        let answer: Value = response.json().await.unwrap();
        if ok {
            Ok(answer["value"].clone())
        } else {
            Err(answer["value"].clone())
        }
    }

    /// Resizes the window to `width`×`height`.
    pub async fn resize(&self, width: u32, height: u32) {
        self.command(
            "POST",
            "/window/rect",
            json!({"width": width, "height": height}),
        )
        .await;
    }

    pub async fn goto(&self, url: &str) {
        self.command("POST", "/url", json!({"url": url})).await;
    }

    /// The element `css` selects, waiting for it to exist.
    pub async fn find(&self, css: &str) -> String {
        let started = Instant::now();
        loop {
            let found = self
                .try_command(
                    "POST",
                    "/element",
                    json!({"using": "css selector", "value": css}),
                )
                .await;
            if let Ok(element) = found {
                return element[ELEMENT]
                    .as_str()
                    .unwrap_or_else(|| panic!("find {css}: {element}"))
                    .to_string();
            }
            assert!(started.elapsed() < PATIENCE, "no element {css}");
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }

    /// The element `css` selects, waiting for it to exist and be shown:
    /// a route's form is in the page before the route shows it.
    pub async fn find_shown(&self, css: &str) -> String {
        let started = Instant::now();
        loop {
            let element = self.find(css).await;
            let shown = self
                .try_command("GET", &format!("/element/{element}/displayed"), json!({}))
                .await;
            if shown == Ok(Value::Bool(true)) {
                return element;
            }
            assert!(started.elapsed() < PATIENCE, "{css} is never shown");
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }

    pub async fn click(&self, css: &str) {
        let element = self.find_shown(css).await;
        self.command("POST", &format!("/element/{element}/click"), json!({}))
            .await;
    }

    /// Types `text` into `css` (for a file input: the file's path).
    pub async fn type_into(&self, css: &str, text: &str) {
        let element = self.find_shown(css).await;
        self.command("POST", &format!("/element/{element}/clear"), json!({}))
            .await;
        self.command(
            "POST",
            &format!("/element/{element}/value"),
            json!({"text": text}),
        )
        .await;
    }

    /// Chooses `file` in a file input.
    pub async fn choose_file(&self, css: &str, file: &Path) {
        let element = self.find(css).await;
        self.command(
            "POST",
            &format!("/element/{element}/value"),
            json!({"text": file.display().to_string()}),
        )
        .await;
    }

    /// Selects the option of value `value` in the select `css`.
    pub async fn select(&self, css: &str, value: &str) {
        self.click(&format!("{css} option[value=\"{value}\"]"))
            .await;
    }

    pub async fn text(&self, css: &str) -> String {
        let element = self.find(css).await;
        let value = self
            .command("GET", &format!("/element/{element}/text"), json!({}))
            .await;
        value.as_str().unwrap_or_default().to_string()
    }

    /// Runs `script` (a function body; `arguments` holds `args`) in the page.
    pub async fn execute(&self, script: &str, args: Value) -> Value {
        self.command(
            "POST",
            "/execute/sync",
            json!({"script": script, "args": args}),
        )
        .await
    }

    /// Waits until the text of `css` satisfies `accept`; returns it.
    pub async fn wait_text(&self, css: &str, what: &str, accept: impl Fn(&str) -> bool) -> String {
        self.wait_text_for(css, what, PATIENCE, accept).await
    }

    pub async fn wait_text_for(
        &self,
        css: &str,
        what: &str,
        patience: Duration,
        accept: impl Fn(&str) -> bool,
    ) -> String {
        let started = Instant::now();
        loop {
            let text = self.text(css).await;
            if accept(&text) {
                return text;
            }
            assert!(
                started.elapsed() < patience,
                "{css} never showed {what}; it shows {text:?}"
            );
            tokio::time::sleep(Duration::from_millis(200)).await;
        }
    }

    /// Waits until `script` returns true.
    pub async fn wait_true(&self, script: &str, what: &str) {
        let started = Instant::now();
        while self.execute(script, json!([])).await != json!(true) {
            assert!(started.elapsed() < PATIENCE, "never: {what}");
            tokio::time::sleep(Duration::from_millis(200)).await;
        }
    }

    /// Saves a PNG of the window.
    pub async fn screenshot(&self, path: &Path) {
        let data = self.command("GET", "/screenshot", json!({})).await;
        let png = decode_base64(data.as_str().unwrap());
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, png).unwrap();
    }

    pub async fn quit(self) {
        let _ = self.try_command("DELETE", "", json!({})).await;
    }
}

/// Waits for a finished download named `name` in `dir`.
pub async fn downloaded(dir: &Path, name: &str) -> PathBuf {
    let path = dir.join(name);
    let started = Instant::now();
    // Chromium writes `name.crdownload` and renames it when complete.
    while !path.exists() {
        assert!(started.elapsed() < PATIENCE, "{name} was not downloaded");
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    path
}

/// Standard base64 (screenshots arrive so).
fn decode_base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let digits: Vec<u8> = text.bytes().filter_map(value).collect();
    let mut out = Vec::with_capacity(digits.len() * 3 / 4);
    for chunk in digits.chunks(4) {
        let mut n = 0u32;
        for (i, d) in chunk.iter().enumerate() {
            n |= u32::from(*d) << (18 - 6 * i);
        }
        let bytes = n.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    out
}
