//! [`Check`]: the validation helpers (finite numbers, directions, colours, positive values)
//! that reject a value with its JSON path and position.
use crate::scene::IntegratorKind;

use super::SceneError;
use super::desc::Triple;
use glam::DVec3;

/// Collects the first validation error with its path.
pub(super) struct Check<'a> {
    pub(super) src: &'a str,
}

impl Check<'_> {
    pub(super) fn fail<T>(
        &self,
        path: impl Into<String>,
        message: impl Into<String>,
    ) -> Result<T, SceneError> {
        let path = path.into();
        let pos = self.position(&path);
        Err(SceneError {
            line: pos.map(|p| p.0),
            column: pos.map(|p| p.1),
            path,
            message: message.into(),
        })
    }

    /// Where the file writes the setting `path` names in the flat record (`settings.rr_depth`):
    /// there in the old spelling, or in `settings.integrator` or an element of
    /// `settings.other_integrators` in the new one; `path` itself when the file does not
    /// write it.
    pub(super) fn settings_key(&self, path: &str) -> String {
        let Some(key) = path.strip_prefix("settings.") else {
            return path.to_string();
        };
        let first = key.split(['.', '[']).next().unwrap_or(key);
        let rest = &key[first.len()..];
        std::iter::once(format!("settings.{first}"))
            .chain(std::iter::once(format!("settings.integrator.{first}")))
            .chain(
                (0..IntegratorKind::ALL.len())
                    .map(|i| format!("settings.other_integrators[{i}].{first}")),
            )
            .find(|p| super::locate(self.src, p).is_some())
            .map_or_else(|| path.to_string(), |p| format!("{p}{rest}"))
    }

    /// Where `path` is, or else its nearest enclosing value that the file writes (a default
    /// such as `camera.up` is not in the text; its `camera` is).
    fn position(&self, path: &str) -> Option<(usize, usize)> {
        let segs = super::path::parse(path)?;
        (0..=segs.len())
            .rev()
            .find_map(|n| super::locate(self.src, &super::path::join(&segs[..n])))
    }

    pub(super) fn finite(&self, path: &str, v: f64) -> Result<f64, SceneError> {
        if v.is_finite() {
            Ok(v)
        } else {
            self.fail(path, format!("must be a finite number, got {v}"))
        }
    }

    pub(super) fn vec(&self, path: &str, v: Triple) -> Result<DVec3, SceneError> {
        for (i, c) in v.iter().enumerate() {
            self.finite(&format!("{path}[{i}]"), *c)?;
        }
        Ok(DVec3::from(v))
    }

    pub(super) fn direction(&self, path: &str, v: Triple) -> Result<DVec3, SceneError> {
        let d = self.vec(path, v)?;
        match d.try_normalize() {
            Some(n) => Ok(n),
            None => self.fail(path, "must be a non-zero direction"),
        }
    }

    pub(super) fn color(&self, path: &str, v: Triple) -> Result<DVec3, SceneError> {
        let c = self.vec(path, v)?;
        if c.min_element() < 0.0 {
            return self.fail(path, format!("must not be negative, got {v:?}"));
        }
        Ok(c)
    }

    pub(super) fn positive(&self, path: &str, v: f64) -> Result<f64, SceneError> {
        if self.finite(path, v)? > 0.0 {
            Ok(v)
        } else {
            self.fail(path, format!("must be positive, got {v}"))
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::Scene;

    #[test]
    fn a_default_value_is_placed_at_what_encloses_it() {
        // No `up`: the default [0, 1, 0] is parallel to a camera looking straight down.
        let src = "{\n  \"camera\": {\"position\": [0,5,0], \"look_at\": [0,0,0], \"fov_y\": 40, \"width\": 4, \"height\": 3}\n}";
        let e = Scene::from_json(src).unwrap_err();
        assert_eq!(e.path, "camera.up");
        assert_eq!((e.line, e.column), (Some(2), Some(13)), "{e}");
    }
}
