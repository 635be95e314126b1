//! The committed JSON Schemas under `docs/schema/` are those the types generate today. After a
//! change to a document's type, regenerate them with
//! `PIM_WRITE_SCHEMA=1 cargo test -p pim-documents --test schema` and commit the files.

use std::path::PathBuf;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/schema")
}

#[test]
fn the_committed_schemas_are_those_the_types_generate() {
    let write = std::env::var_os("PIM_WRITE_SCHEMA").is_some();
    if write {
        std::fs::create_dir_all(dir()).unwrap();
    }
    let mut stale = Vec::new();
    for doc in pim_documents::schema::documents() {
        let text = serde_json::to_string_pretty(&doc.schema).unwrap() + "\n";
        let path = dir().join(doc.file);
        if write {
            std::fs::write(&path, &text).unwrap();
        } else if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
            stale.push(doc.file);
        }
    }
    assert!(
        stale.is_empty(),
        "docs/schema/ is not what the types generate: {stale:?}; regenerate with \
         PIM_WRITE_SCHEMA=1 cargo test -p pim-documents --test schema"
    );
    // Nothing else lives there but the index.
    let mut files: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|f| f.ends_with(".schema.json"))
        .collect();
    files.sort();
    let mut expected: Vec<String> = pim_documents::schema::DOCUMENTS
        .iter()
        .map(|(f, _)| f.to_string())
        .collect();
    expected.sort();
    assert_eq!(files, expected);
}

#[test]
fn every_schema_describes_an_object_with_documented_fields() {
    for doc in pim_documents::schema::documents() {
        let v = serde_json::to_value(&doc.schema).unwrap();
        assert_eq!(v["type"], "object", "{}", doc.file);
        let props = v["properties"].as_object().unwrap();
        assert!(!props.is_empty(), "{}", doc.file);
        for (name, p) in props {
            assert!(
                p.get("description").is_some()
                    || p.get("$ref").is_some()
                    || p.get("allOf").is_some(),
                "{}: {name} has no description",
                doc.file
            );
        }
    }
}
