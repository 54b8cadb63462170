//! The URL fragment a link carries (`#scene=caustic&pixel=104,113&integrator=path&spp=16`): the
//! fixture, the selected pixel and settings, so a slide can link to an exact tree.

use raytree::scene::{IntegratorKind, Settings};

/// What a fragment asks for; absent keys leave the page as it is.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Fragment {
    /// A built-in fixture's name (`scene=`).
    pub scene: Option<String>,
    /// The pixel to trace (`pixel=x,y`).
    pub pixel: Option<[u32; 2]>,
    /// `integrator=whitted|path|light|bdpt`.
    pub integrator: Option<IntegratorKind>,
    /// `spp=N` (samples per pixel).
    pub spp: Option<u32>,
    /// `depth=N` (the deepest recursion, `settings.max_depth`).
    pub depth: Option<u32>,
    /// `seed=N`.
    pub seed: Option<u64>,
}

/// The keys a fragment may hold, for the error message.
pub const KEYS: &str = "scene, pixel, integrator, spp, depth, seed";

impl Fragment {
    /// Parse `text` (with or without its leading `#`); an empty fragment asks for nothing.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut f = Self::default();
        let text = text.strip_prefix('#').unwrap_or(text);
        for part in text.split('&').filter(|p| !p.is_empty()) {
            let (key, value) = part
                .split_once('=')
                .ok_or_else(|| format!("URL fragment: {part:?} is not key=value"))?;
            let bad = |what: &str| format!("URL fragment: {key}={value:?}: expected {what}");
            match key {
                "scene" => {
                    if crate::fixtures::get(value).is_none() {
                        let names: Vec<&str> =
                            crate::fixtures::FIXTURES.iter().map(|(n, _)| *n).collect();
                        return Err(bad(&format!("one of {}", names.join(", "))));
                    }
                    f.scene = Some(value.to_owned());
                }
                "pixel" => {
                    let (x, y) = value.split_once(',').ok_or_else(|| bad("x,y"))?;
                    let x = x.parse().map_err(|_| bad("x,y (whole numbers)"))?;
                    let y = y.parse().map_err(|_| bad("x,y (whole numbers)"))?;
                    f.pixel = Some([x, y]);
                }
                "integrator" => {
                    f.integrator = Some(
                        serde_json::from_value(serde_json::Value::String(value.to_owned()))
                            .map_err(|_| bad("whitted, path, light or bdpt"))?,
                    );
                }
                "spp" => f.spp = Some(value.parse().map_err(|_| bad("a whole number"))?),
                "depth" => {
                    let d = value.parse().map_err(|_| bad("a whole number"))?;
                    if d > crate::files::MAX_DEPTH {
                        return Err(format!("URL fragment: {}", crate::files::depth_error(d)));
                    }
                    f.depth = Some(d);
                }
                "seed" => f.seed = Some(value.parse().map_err(|_| bad("a whole number"))?),
                _ => return Err(format!("URL fragment: unknown key {key:?} (known: {KEYS})")),
            }
        }
        Ok(f)
    }

    /// `settings` with this fragment's settings applied.
    #[must_use]
    pub fn settings(&self, mut settings: Settings) -> Settings {
        if let Some(i) = self.integrator {
            settings.integrator = i;
        }
        if let Some(n) = self.spp {
            settings.spp = n;
        }
        if let Some(d) = self.depth {
            settings.max_depth = d;
        }
        if let Some(s) = self.seed {
            settings.seed = s;
        }
        settings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_teachers_link_parses_and_bad_ones_say_why() {
        let f = Fragment::parse("#scene=caustic&pixel=104,113&integrator=path&spp=16").unwrap();
        assert_eq!(f.scene.as_deref(), Some("caustic"));
        assert_eq!(f.pixel, Some([104, 113]));
        assert_eq!(f.integrator, Some(IntegratorKind::Path));
        assert_eq!(f.spp, Some(16));
        let s = f.settings(Settings::default());
        assert_eq!((s.integrator, s.spp), (IntegratorKind::Path, 16));
        assert_eq!(Fragment::parse("").unwrap(), Fragment::default());
        for (name, kind) in [
            ("light", IntegratorKind::Light),
            ("bdpt", IntegratorKind::Bdpt),
        ] {
            let f = Fragment::parse(&format!("integrator={name}")).unwrap();
            assert_eq!(f.integrator, Some(kind), "{name}");
        }
        for (text, want) in [
            ("scene=nope", "expected one of absorption, caustic"),
            ("pixel=3", "expected x,y"),
            ("pixel=a,2", "whole numbers"),
            ("integrator=mlt", "whitted, path, light or bdpt"),
            ("spp=-1", "a whole number"),
            ("zoom=2", "unknown key \"zoom\""),
            ("scene", "is not key=value"),
            ("depth=1024", "deeper than the web page traces (512"),
        ] {
            let e = Fragment::parse(text).unwrap_err();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
