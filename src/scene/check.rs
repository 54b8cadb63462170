//! [`Check`]: the validation helpers (finite numbers, directions, colours, positive values)
//! that reject a value with its JSON path and position.

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
        let pos = super::locate(self.src, &path);
        Err(SceneError {
            line: pos.map(|p| p.0),
            column: pos.map(|p| p.1),
            path,
            message: message.into(),
        })
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
