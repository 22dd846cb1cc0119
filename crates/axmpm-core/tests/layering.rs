//! The engine's module layering, held by a test: a module may use only modules of a lower layer
//! (or itself), so that no two modules depend on each other and a reader can learn the engine
//! from the bottom up. A new top-level module must be given a layer here.
use std::collections::BTreeMap;
use std::path::Path;

/// Layers from the bottom: data types and kinematics, then what is built on them.
const LAYERS: &[&[&str]] = &[
    &["formulation", "grid", "particles"],
    &["geometry", "interpolation"],
    &["config"],
    &["material", "constraint"],
    &["setup", "solver"],
    &["simulation"],
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|layer| layer.contains(&module))
}

/// Every `crate::MODULE` named in code (comment lines left out), with the file and line.
fn uses(dir: &Path, top: Option<&str>, found: &mut Vec<(String, String, String)>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            uses(&path, Some(top.unwrap_or(&name)), found);
            continue;
        }
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let module = top.unwrap_or(&name).to_string();
        let text = std::fs::read_to_string(&path).unwrap();
        for (k, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap();
            let mut rest = code;
            while let Some(at) = rest.find("crate::") {
                rest = &rest[at + "crate::".len()..];
                let used: String = rest.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
                if !used.is_empty() {
                    found.push((module.clone(), used, format!("{}:{}", path.display(), k + 1)));
                }
            }
        }
    }
}

#[test]
fn every_module_uses_only_lower_layers() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut found = Vec::new();
    uses(&src, None, &mut found);
    assert!(found.len() > 20, "the scan found only {} uses: is it reading the sources?", found.len());
    let mut wrong: BTreeMap<String, String> = BTreeMap::new();
    for (module, used, place) in found {
        if module == "lib" || module == used {
            continue;
        }
        match (layer_of(&module), layer_of(&used)) {
            (Some(a), Some(b)) if b < a => {}
            (Some(_), Some(_)) => {
                wrong.entry(format!("{module} -> {used}")).or_insert(place);
            }
            (None, _) => {
                wrong.entry(format!("{module} has no layer")).or_insert(place);
            }
            (_, None) => {
                wrong.entry(format!("{used} has no layer")).or_insert(place);
            }
        }
    }
    let report: Vec<String> = wrong.into_iter().map(|(edge, place)| format!("{edge} (first at {place})")).collect();
    assert!(report.is_empty(), "uses against the layering (tests/layering.rs):\n{}", report.join("\n"));
}
