//! The server's write side through its HTTP routes (the router itself, no browser): a save
//! over a file changed on disk refused, two clients on one file, only regular files opened,
//! the headers of every answer, and studies that never hold up a live answer.

use crate::example;
use axum::body::Body;
use axum::http::{header, Request, StatusCode};
use http_body_util::BodyExt;
use serde_json::{json, Value};
use std::path::Path;
use std::time::{Duration, Instant};
use tower::ServiceExt;

pub(crate) const TOKEN: &str = "0123456789abcdef0123456789abcdef";
const CASE: &str = "reconstruction_us.toml";

/// A folder with the example case, and the server's app on it.
fn served() -> (tempfile::TempDir, axum::Router) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join(CASE), example(CASE)).unwrap();
    let app = app_on(dir.path());
    (dir, app)
}

/// The server's app on the folder `root`, with the tests' token.
pub(crate) fn app_on(root: &Path) -> axum::Router {
    pim_serve::app(pim_serve::Served {
        root: root.to_path_buf(),
        initial: None,
        token: TOKEN.into(),
        hosts: vec![],
    })
}

pub(crate) fn request(method: &str, uri: &str, body: Option<Value>) -> Request<Body> {
    let b = Request::builder()
        .method(method)
        .uri(uri)
        .header(header::HOST, "127.0.0.1:8765")
        .header(header::COOKIE, format!("pim_token={TOKEN}"));
    match body {
        Some(v) => b
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(v.to_string()))
            .unwrap(),
        None => b.body(Body::empty()).unwrap(),
    }
}

pub(crate) async fn send(
    app: &axum::Router,
    req: Request<Body>,
) -> (StatusCode, axum::http::HeaderMap, Vec<u8>) {
    let res = app.clone().oneshot(req).await.unwrap();
    let (parts, body) = res.into_parts();
    let bytes = body.collect().await.unwrap().to_bytes().to_vec();
    (parts.status, parts.headers, bytes)
}

pub(crate) async fn call(
    app: &axum::Router,
    method: &str,
    uri: &str,
    body: Option<Value>,
) -> (StatusCode, Value) {
    let (status, _, bytes) = send(app, request(method, uri, body)).await;
    (
        status,
        serde_json::from_slice(&bytes).unwrap_or(Value::Null),
    )
}

/// The page's Save of `text` into `path` over `version`.
async fn save(app: &axum::Router, path: &str, text: &str, version: &str) -> (StatusCode, Value) {
    call(
        app,
        "POST",
        "/api/save",
        Some(json!({ "path": path, "text": text, "version": version })),
    )
    .await
}

async fn open(app: &axum::Router, path: &str) -> (String, String) {
    let (status, v) = call(app, "GET", &format!("/api/case?path={path}"), None).await;
    assert_eq!(status, StatusCode::OK, "{v}");
    (
        v["text"].as_str().unwrap().to_string(),
        v["version"].as_str().unwrap().to_string(),
    )
}

fn with_mass(text: &str, mass: u32) -> String {
    let mut e = pim_case::edit::CaseEdit::new(CASE, text).unwrap();
    e.set(
        "vehicle1.mass",
        pim_case::edit::NewValue::Written(f64::from(mass)),
    )
    .unwrap();
    e.text()
}

/// The probe that once lost a user's change: the page opened the case, another editor changed
/// the friction and appended a line, the page saved its own edit. Now the save is refused
/// (409) with the file's text as it is on disk, nothing is overwritten, and a save over the
/// version on disk (the page's "save mine over it") goes through.
#[tokio::test]
async fn a_save_over_a_file_changed_on_disk_is_refused() {
    let (dir, app) = served();
    let (text, version) = open(&app, CASE).await;
    let outside = text.replace("friction = 0.72", "friction = 0.65") + "# checked on site\n";
    std::fs::write(dir.path().join(CASE), &outside).unwrap();
    let mine = with_mass(&text, 3500);
    let (status, v) = save(&app, CASE, &mine, &version).await;
    assert_eq!(status, StatusCode::CONFLICT, "{v}");
    assert_eq!(v["conflict"]["text"], outside.as_str());
    assert!(
        v["error"].as_str().unwrap().contains("changed on disk"),
        "{v}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join(CASE)).unwrap(),
        outside
    );
    // Without a version a save is refused too (it could not tell).
    let (status, _) = call(
        &app,
        "POST",
        "/api/save",
        Some(json!({ "path": CASE, "text": mine })),
    )
    .await;
    assert_eq!(status, StatusCode::PRECONDITION_REQUIRED);
    // Over the version on disk: written, with its new version.
    let now = v["conflict"]["version"].as_str().unwrap();
    let (status, v) = save(&app, CASE, &mine, now).await;
    assert_eq!(status, StatusCode::OK, "{v}");
    assert_eq!(
        std::fs::read_to_string(dir.path().join(CASE)).unwrap(),
        mine
    );
    assert_eq!(v["version"], pim_store::Version::of(&mine).0.as_str());
}

/// The values `pim set` refuses are refused by the page's Save too (422, `pim fit`'s message),
/// and the file is left as it was.
#[tokio::test]
async fn a_save_pim_fit_would_refuse_is_refused() {
    let (dir, app) = served();
    let (text, version) = open(&app, CASE).await;
    for (key, value) in [
        ("observations.0.sigma", json!(-1.0)),
        ("observations.0.sigma", json!(0.0)),
        ("pre_impact.vehicle1.skid", json!(-42.0)),
        ("runout.vehicle1.wheelbase", json!(-5.0)),
        ("pre_impact.vehicle1.braking", json!(7.0)),
        ("runout.vehicle2.wheels", json!("flying")),
        ("runout.friction", json!(-1.0)),
        ("runout.friction", json!(0.0)),
        ("runout.friction", json!(5.0)),
        ("runout.friction", json!(1e-320)),
        ("scene.vehicle1.rest.heading", json!(1e9)),
        ("runout.vehicle1.braking", json!(7.0)),
        ("scene.vehicle1.rest_sigma.x", json!(-1.0)),
        ("pre_impact.vehicle2.edr.0.sigma", json!(0.0)),
    ] {
        let mut e = pim_case::edit::CaseEdit::new(CASE, &text).unwrap();
        let v = match &value {
            Value::String(s) => pim_case::edit::NewValue::Text(s.clone()),
            x => pim_case::edit::NewValue::Written(x.as_f64().unwrap()),
        };
        e.set(key, v).unwrap();
        let (status, v) = save(&app, CASE, &e.text(), &version).await;
        assert_eq!(
            status,
            StatusCode::UNPROCESSABLE_ENTITY,
            "{key}={value}: {v}"
        );
        let why = v["error"].as_str().unwrap();
        assert!(
            why.starts_with("not saved: reconstruction_us.toml:"),
            "{why}"
        );
        assert_eq!(
            std::fs::read_to_string(dir.path().join(CASE)).unwrap(),
            text
        );
    }
}

/// Two clients, each 50 times opening, editing and saving its own value over the version it
/// read, while a third reads: no read sees an empty or partial file, every save either goes
/// through or is told the file changed (and then saves again over the new version), the file
/// always parses, and it ends with both clients' last values.
#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn two_clients_hammering_one_file() {
    let (dir, app) = served();
    let file = dir.path().join(CASE);
    let reader = {
        let app = app.clone();
        tokio::spawn(async move {
            let mut reads = 0;
            for _ in 0..150 {
                let (text, _) = open(&app, CASE).await;
                assert!(
                    pim_case::case::Case::from_text(CASE, &text).is_ok(),
                    "a read of {} bytes does not parse",
                    text.len()
                );
                reads += 1;
            }
            reads
        })
    };
    let clients: Vec<_> = ["vehicle1.mass", "vehicle2.mass"]
        .into_iter()
        .map(|key| {
            let app = app.clone();
            tokio::spawn(async move {
                let mut conflicts = 0;
                for i in 0..50u32 {
                    loop {
                        let (text, version) = open(&app, CASE).await;
                        let mut e = pim_case::edit::CaseEdit::new(CASE, &text).unwrap();
                        e.set(key, pim_case::edit::NewValue::Written(f64::from(3000 + i)))
                            .unwrap();
                        let (status, v) = save(&app, CASE, &e.text(), &version).await;
                        match status {
                            StatusCode::OK => break,
                            StatusCode::CONFLICT => conflicts += 1,
                            s => panic!("{key} {i}: {s}: {v}"),
                        }
                    }
                }
                conflicts
            })
        })
        .collect();
    let mut conflicts = 0;
    for c in clients {
        conflicts += c.await.unwrap();
    }
    assert_eq!(reader.await.unwrap(), 150);
    let last = std::fs::read_to_string(&file).unwrap();
    let e = pim_case::edit::CaseEdit::new(CASE, &last).unwrap();
    assert_eq!(e.get("vehicle1.mass").unwrap(), "3049.0");
    assert_eq!(e.get("vehicle2.mass").unwrap(), "3049.0");
    println!("two clients, 50 saves each: {conflicts} saves told the file had changed");
}

/// A FIFO named like a case is neither listed nor opened (the server does not hang on it); a
/// 60 MB case is refused by its size.
#[tokio::test]
async fn only_regular_files_of_a_case_s_size_are_opened() {
    let (dir, app) = served();
    let fifo = dir.path().join("pipe.toml");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let huge = dir.path().join("huge.toml");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len(60 << 20)
        .unwrap();
    let started = Instant::now();
    let (status, v) = call(&app, "GET", "/api/cases", None).await;
    assert_eq!(status, StatusCode::OK);
    let cases: Vec<&str> = v["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap())
        .collect();
    assert_eq!(cases, vec!["huge.toml", CASE]);
    let (status, v) = call(&app, "GET", "/api/case?path=pipe.toml", None).await;
    assert_eq!(status, StatusCode::FORBIDDEN, "{v}");
    assert!(
        v["error"].as_str().unwrap().contains("not a regular file"),
        "{v}"
    );
    let (status, v) = call(&app, "GET", "/api/case?path=huge.toml", None).await;
    assert_eq!(status, StatusCode::FORBIDDEN, "{v}");
    assert!(v["error"].as_str().unwrap().contains("larger than"), "{v}");
    let (status, _) = save(&app, "pipe.toml", &example(CASE), "00000000").await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let (status, _) = call(
        &app,
        "POST",
        "/api/batch",
        Some(json!({ "paths": ["pipe.toml"] })),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    assert!(started.elapsed() < Duration::from_secs(5));
}

/// A read-only file is not saved over (and keeps its mode); a file reached through a link is
/// edited where it lies and the link kept.
#[tokio::test]
async fn a_read_only_file_and_a_linked_one() {
    use std::os::unix::fs::PermissionsExt;
    let (dir, app) = served();
    let file = dir.path().join(CASE);
    let (text, version) = open(&app, CASE).await;
    std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o444)).unwrap();
    let (status, v) = save(&app, CASE, &with_mass(&text, 3500), &version).await;
    assert_eq!(status, StatusCode::FORBIDDEN, "{v}");
    assert!(v["error"].as_str().unwrap().contains("read-only"), "{v}");
    assert_eq!(
        std::fs::metadata(&file).unwrap().permissions().mode() & 0o777,
        0o444
    );
    std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o640)).unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    std::os::unix::fs::symlink(&file, sub.join("linked.toml")).unwrap();
    let (text, version) = open(&app, "sub/linked.toml").await;
    let (status, v) = save(&app, "sub/linked.toml", &with_mass(&text, 3600), &version).await;
    assert_eq!(status, StatusCode::OK, "{v}");
    assert!(std::fs::symlink_metadata(sub.join("linked.toml"))
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(std::fs::read_to_string(&file)
        .unwrap()
        .contains("mass = 3600.0"));
    assert_eq!(
        std::fs::metadata(&file).unwrap().permissions().mode() & 0o777,
        0o640
    );
}

/// Every answer says its type is the one given and carries a policy; an image is typed by its
/// bytes and sandboxed (an SVG's script never runs on the editor's origin); a request with
/// two Host headers, or a token one character off, is refused.
#[tokio::test]
async fn the_headers_of_every_answer() {
    let (dir, app) = served();
    std::fs::write(
        dir.path().join("evil.svg"),
        r#"<?xml version="1.0"?><!-- a diagram --><svg xmlns="http://www.w3.org/2000/svg"><script>alert(1)</script></svg>"#,
    )
    .unwrap();
    std::fs::write(
        dir.path().join("fake.png"),
        "<html><script>alert(1)</script></html>",
    )
    .unwrap();
    let (status, headers, _) = send(&app, request("GET", "/", None)).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(headers[header::X_CONTENT_TYPE_OPTIONS], "nosniff");
    let csp = headers[header::CONTENT_SECURITY_POLICY].to_str().unwrap();
    assert!(
        csp.contains("script-src 'self'") && csp.contains("object-src 'none'"),
        "{csp}"
    );
    let (status, headers, _) = send(&app, request("GET", "/api/image?path=evil.svg", None)).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(headers[header::CONTENT_TYPE], "image/svg+xml");
    assert!(headers[header::CONTENT_SECURITY_POLICY]
        .to_str()
        .unwrap()
        .starts_with("sandbox;"));
    assert_eq!(headers[header::X_CONTENT_TYPE_OPTIONS], "nosniff");
    let (status, _, _) = send(&app, request("GET", "/api/image?path=fake.png", None)).await;
    assert_eq!(status, StatusCode::UNSUPPORTED_MEDIA_TYPE);
    let png = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scene/intersection.png");
    std::fs::copy(png, dir.path().join("scene.png")).unwrap();
    let (status, headers, _) = send(&app, request("GET", "/api/image?path=scene.png", None)).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(headers[header::CONTENT_TYPE], "image/png");
    // Two Host headers: refused, whichever comes first.
    let mut req = request("GET", "/api/cases", None);
    req.headers_mut()
        .append(header::HOST, "evil.example".parse().unwrap());
    let (status, _, _) = send(&app, req).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    let mut off = TOKEN.to_string();
    off.replace_range(31..32, "e");
    let mut req = request("GET", "/api/cases", None);
    req.headers_mut()
        .insert(header::COOKIE, format!("pim_token={off}").parse().unwrap());
    let (status, _, _) = send(&app, req).await;
    assert_eq!(status, StatusCode::FORBIDDEN);
}

/// 40 studies asked at once: the first 8 are taken (2 computing, 6 waiting), the rest refused
/// with 429 and a reason; all cancelled, every one ends, and new ones are taken again.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn forty_studies_asked_at_once() {
    let (_dir, app) = served();
    let text = example(CASE);
    let mut taken = Vec::new();
    let mut refused = 0;
    for _ in 0..40 {
        let (status, v) = call(
            &app,
            "POST",
            "/api/study",
            Some(json!({ "path": CASE, "text": text, "draws": 100000 })),
        )
        .await;
        match status {
            StatusCode::OK => taken.push(v["id"].as_u64().unwrap()),
            StatusCode::TOO_MANY_REQUESTS => {
                assert!(v["error"].as_str().unwrap().contains("cancel one"), "{v}");
                refused += 1;
            }
            s => panic!("{s}: {v}"),
        }
    }
    assert_eq!((taken.len(), refused), (8, 32));
    for id in &taken {
        let (status, _) = call(&app, "POST", "/api/study/cancel", Some(json!({ "id": id }))).await;
        assert_eq!(status, StatusCode::OK);
    }
    let deadline = Instant::now() + Duration::from_secs(60);
    for id in &taken {
        loop {
            let (_, v) = call(&app, "GET", &format!("/api/study?id={id}"), None).await;
            let state = v["state"].as_str().unwrap().to_string();
            if state != "running" && state != "waiting" {
                assert_eq!(state, "cancelled", "{v}");
                break;
            }
            assert!(
                Instant::now() < deadline,
                "study {id} did not end after its cancel"
            );
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }
    let (status, _) = call(
        &app,
        "POST",
        "/api/study",
        Some(json!({ "path": CASE, "text": text, "draws": 2 })),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
}

/// Live answers while a study computes: the study runs on threads of its own at a lower
/// priority, so a drag's answer is not queued behind its draws. Measured: the median of 10
/// live answers before, and of 10 while a 2,000-draw study runs.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_study_does_not_hold_up_a_live_answer() {
    let (_dir, app) = served();
    let text = example(CASE);
    let (status, _) = call(
        &app,
        "POST",
        "/api/answer",
        Some(json!({ "path": CASE, "text": text })),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    let moved =
        |k: u32| pim_serve::move_rest(CASE, &text, 2, [79.7 + 0.1 * f64::from(k), 50.1]).unwrap();
    let live = |k: u32| {
        let app = app.clone();
        let t = moved(k);
        async move {
            let started = Instant::now();
            let (status, v) = call(
                &app,
                "POST",
                "/api/answer",
                Some(json!({ "path": CASE, "text": t, "live": true })),
            )
            .await;
            assert_eq!(status, StatusCode::OK, "{v}");
            started.elapsed().as_secs_f64() * 1e3
        }
    };
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let mut before = Vec::new();
    for k in 0..10 {
        before.push(live(k).await);
    }
    let (status, v) = call(
        &app,
        "POST",
        "/api/study",
        Some(json!({ "path": CASE, "text": text, "draws": 2000 })),
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    let id = v["id"].as_u64().unwrap();
    tokio::time::sleep(Duration::from_millis(300)).await;
    let mut during = Vec::new();
    for k in 0..10 {
        during.push(live(k).await);
    }
    let (_, v) = call(&app, "GET", &format!("/api/study?id={id}"), None).await;
    assert_eq!(
        v["state"], "running",
        "the study ended before the answers were timed: {v}"
    );
    call(&app, "POST", "/api/study/cancel", Some(json!({ "id": id }))).await;
    let (b, d) = (median(before.clone()), median(during.clone()));
    println!(
        "live answers: median {b:.1} ms alone, {d:.1} ms during a study (max {:.1})",
        during.iter().cloned().fold(0.0, f64::max)
    );
    // Before, a 300-draw study made a 17 ms answer take 5.7 s: the answer waited for the
    // study's draws. On a study's own niced threads it shares the cores at most evenly.
    assert!(
        d < 3.0 * b + 20.0,
        "median {d:.1} ms during a study against {b:.1} ms alone"
    );
}
