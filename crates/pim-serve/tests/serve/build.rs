//! A case built in the page from an empty folder: named and started (nothing written), its
//! survey imported and drawn before it is a case, its sections added, created on Save (never
//! over a file of that name), and what `pim fit` reads.
use crate::writes::{app_on, call};
use axum::http::StatusCode;
use serde_json::{json, Value};

fn empty() -> (tempfile::TempDir, axum::Router) {
    let dir = tempfile::tempdir().unwrap();
    let app = app_on(dir.path());
    (dir, app)
}

async fn post(app: &axum::Router, url: &str, body: Value) -> (StatusCode, Value) {
    call(app, "POST", url, Some(body)).await
}

#[tokio::test]
async fn a_case_is_built_from_an_empty_folder() {
    let (dir, app) = empty();
    let (s, v) = post(
        &app,
        "/api/new",
        json!({ "name": "main_and_oak", "units": "us", "convention": "sae" }),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["path"], "main_and_oak.toml");
    let mut text = v["text"].as_str().unwrap().to_string();
    assert!(
        text.contains("title = \"main and oak\"\nconvention = \"sae\""),
        "{text}"
    );
    // Nothing written until saved.
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none());
    // Not yet a case: the answer says why, with the plan of what it gives (its survey).
    let csv = "id,x,y,code\nH,0,0,HYD\nR1,40.5,10.25,REST\nR2,35,60,REST\n";
    let (s, v) = post(
        &app,
        "/api/survey",
        json!({ "path": "main_and_oak.toml", "text": text, "csv": csv, "source": "survey.csv" }),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    text = v["text"].as_str().unwrap().to_string();
    let (s, v) = post(
        &app,
        "/api/answer",
        json!({ "path": "main_and_oak.toml", "text": text }),
    )
    .await;
    assert_eq!(s, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(v["error"].as_str().unwrap().contains("vehicle1"), "{v}");
    let survey = v["sketch"]["survey"].as_array().unwrap();
    assert_eq!(survey.len(), 3);
    // SAE: a map, x up: R1 (x 40.5, y 10.25) at page (10.25, 40.5).
    assert_eq!(survey[1]["at"], json!([10.25, 40.5]));
    // Saving it now is refused: pim fit would refuse it.
    let (s, v) = post(
        &app,
        "/api/save",
        json!({ "path": "main_and_oak.toml", "text": text, "create": true }),
    )
    .await;
    assert_eq!(s, StatusCode::UNPROCESSABLE_ENTITY, "{v}");
    // Every section the menu offers, added in its order.
    let (_, v) = post(
        &app,
        "/api/sections",
        json!({ "path": "main_and_oak.toml", "text": text }),
    )
    .await;
    let names: Vec<String> = v["sections"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(names.len(), pim_case::templates::SECTIONS.len());
    for name in &names {
        let (s, v) = post(
            &app,
            "/api/section",
            json!({ "path": "main_and_oak.toml", "text": text, "name": name }),
        )
        .await;
        assert_eq!(s, StatusCode::OK, "{name}: {v}");
        text = v["text"].as_str().unwrap().to_string();
    }
    let (_, v) = post(
        &app,
        "/api/sections",
        json!({ "path": "main_and_oak.toml", "text": text }),
    )
    .await;
    assert_eq!(v["sections"], json!([]));
    // The rests placed on the survey's points keep their ids: a section each, added at the
    // end; placed again, the rest is moved in it.
    for (vehicle, point, heading) in [(1, "R1", 144.0), (2, "R2", 241.0), (1, "R1", 145.0)] {
        let (s, v) = post(&app, "/api/rest", json!({ "path": "main_and_oak.toml", "text": text, "vehicle": vehicle, "at": [0.0, 0.0], "heading": heading, "sigma": 1.0, "point": point })).await;
        assert_eq!(s, StatusCode::OK, "{v}");
        text = v["text"].as_str().unwrap().to_string();
    }
    assert!(
        text.ends_with(
            "\n\n[scene.vehicle1]\nrest = { x = 40.5, y = 10.25, heading = 145.0, point = \"R1\" }\n\
             rest_sigma = { x = 1.0, y = 1.0, heading = 3.0 }\n\n[scene.vehicle2]\n\
             rest = { x = 35.0, y = 60.0, heading = 241.0, point = \"R2\" }\n\
             rest_sigma = { x = 1.0, y = 1.0, heading = 3.0 }\n"
        ),
        "{text}"
    );
    // Off the survey, where the page was clicked (feet, the SAE page's right is y).
    let (s, v) = post(&app, "/api/rest", json!({ "path": "main_and_oak.toml", "text": text, "vehicle": 2, "at": [61.234, 36.0], "sigma": 0.5 })).await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert!(
        v["text"]
            .as_str()
            .unwrap()
            .contains("rest = { x = 36.0, y = 61.23 }"),
        "{v}"
    );
    // Now a case: it answers, and saves by creating its file.
    let (s, v) = post(
        &app,
        "/api/answer",
        json!({ "path": "main_and_oak.toml", "text": text }),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(v["question"], "reconstruction");
    let (s, v) = post(
        &app,
        "/api/save",
        json!({ "path": "main_and_oak.toml", "text": text, "create": true }),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    assert_eq!(
        std::fs::read_to_string(dir.path().join("main_and_oak.toml")).unwrap(),
        text
    );
    // A second create of that name is refused, the file kept; so is a new case of that name.
    let (s, v) = post(
        &app,
        "/api/save",
        json!({ "path": "main_and_oak.toml", "text": "title = \"x\"", "create": true }),
    )
    .await;
    assert!(
        s == StatusCode::FORBIDDEN || s == StatusCode::UNPROCESSABLE_ENTITY,
        "{s} {v}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("main_and_oak.toml")).unwrap(),
        text
    );
    let (s, v) = post(
        &app,
        "/api/save",
        json!({ "path": "main_and_oak.toml", "text": text, "create": true }),
    )
    .await;
    assert_eq!(s, StatusCode::FORBIDDEN, "{v}");
    assert!(
        v["error"].as_str().unwrap().contains("exists already"),
        "{v}"
    );
    let (s, _) = post(&app, "/api/new", json!({ "name": "main_and_oak.toml" })).await;
    assert_eq!(s, StatusCode::CONFLICT);
    // A name outside the folder is refused.
    let (s, _) = post(&app, "/api/new", json!({ "name": "../elsewhere" })).await;
    assert_eq!(s, StatusCode::FORBIDDEN);
    let (s, _) = post(
        &app,
        "/api/new",
        json!({ "name": "a", "units": "furlongs" }),
    )
    .await;
    assert_eq!(s, StatusCode::UNPROCESSABLE_ENTITY);
}
