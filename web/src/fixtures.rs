//! The scenes built into the page: every fixture of `fixtures/` whose meshes ship with the
//! repository (`fixtures/mesh/bunny.json` reads an OBJ from outside it: open it with its OBJ
//! through the file picker instead).

/// `(name, JSON)` of each built-in scene, in the picker's order (alphabetical).
pub const FIXTURES: &[(&str, &str)] = &[
    ("absorption", include_str!("../../fixtures/absorption.json")),
    ("caustic", include_str!("../../fixtures/caustic.json")),
    ("classic", include_str!("../../fixtures/classic.json")),
    (
        "cornell-box",
        include_str!("../../fixtures/cornell-box.json"),
    ),
    (
        "depth-of-field",
        include_str!("../../fixtures/depth-of-field.json"),
    ),
    ("diffuse", include_str!("../../fixtures/diffuse.json")),
    ("glossy", include_str!("../../fixtures/glossy.json")),
    ("metals", include_str!("../../fixtures/metals.json")),
    ("mirrors", include_str!("../../fixtures/mirrors.json")),
    ("nested", include_str!("../../fixtures/nested.json")),
    ("plastic", include_str!("../../fixtures/plastic.json")),
    ("slab", include_str!("../../fixtures/slab.json")),
    (
        "soft-shadows",
        include_str!("../../fixtures/soft-shadows.json"),
    ),
    ("spot", include_str!("../../fixtures/spot.json")),
    ("tir-block", include_str!("../../fixtures/tir-block.json")),
    (
        "translucent-shadow",
        include_str!("../../fixtures/translucent-shadow.json"),
    ),
    (
        "water-grazing",
        include_str!("../../fixtures/water-grazing.json"),
    ),
];

/// The fixture shown when the URL names none.
pub const DEFAULT: &str = "classic";

/// The path a fixture is opened under (what the title bar and the export names show).
#[must_use]
pub fn path_of(name: &str) -> String {
    format!("fixtures/{name}.json")
}

/// The fixture `name`, if built in.
#[must_use]
pub fn get(name: &str) -> Option<&'static str> {
    FIXTURES.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_self_contained_fixture_is_built_in_and_parses() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures");
        let mut on_disk: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| {
                let name = e.unwrap().file_name().into_string().unwrap();
                name.strip_suffix(".json").map(str::to_owned)
            })
            .collect();
        on_disk.sort();
        let built_in: Vec<&str> = FIXTURES.iter().map(|(n, _)| *n).collect();
        assert_eq!(built_in, on_disk);
        for (name, json) in FIXTURES {
            raytree::Scene::from_json(json).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        assert!(get(DEFAULT).is_some());
    }
}
