//! The Mitsuba XML as an owned tree: includes spliced, `$variables` substituted, old spellings
//! upgraded, ids indexed.

use crate::formats::{FormatError, Limits, Resolver, relative_to};
use std::collections::HashMap;
use std::rc::Rc;

/// An element with its attributes, children and position.
#[derive(Clone, Debug)]
pub struct El {
    /// Tag name (upgraded: `lookAt` -> `lookat`).
    pub tag: String,
    /// Attributes in order (values substituted; `name` upgraded).
    pub attrs: Vec<(String, String)>,
    /// Child elements.
    pub children: Vec<El>,
    /// The file it is in.
    pub file: Rc<str>,
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
}

impl El {
    /// Attribute `name`.
    #[must_use]
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// `<tag type="..." id="...">` for messages.
    #[must_use]
    pub fn label(&self) -> String {
        let mut s = format!("<{}", self.tag);
        for k in ["type", "name", "id"] {
            if let Some(v) = self.attr(k) {
                s.push_str(&format!(" {k}=\"{v}\""));
            }
        }
        s.push('>');
        s
    }

    /// An error at this element.
    #[must_use]
    pub fn err(&self, msg: impl std::fmt::Display) -> FormatError {
        FormatError {
            file: self.file.to_string(),
            line: self.line,
            column: self.column,
            message: format!("{}: {msg}", self.label()),
        }
    }
}

/// Reads the XML of the top file and its includes.
pub struct Reader<'r> {
    pub res: &'r mut dyn Resolver,
    limits: Limits,
    vars: HashMap<String, String>,
    defines: HashMap<String, String>,
    open: Vec<String>,
    pub files: usize,
    /// Objects by id.
    pub ids: Rc<HashMap<String, El>>,
    /// Version of the top file (major, minor).
    pub version: (u32, u32),
    /// Directories `<path value>` added to the search for files, the latest first (each as
    /// named relative to the scene: joined to the directory of the file it is in).
    pub search: Vec<String>,
    /// `<alias id as>` pairs in file order, with the element for messages.
    aliases: Vec<El>,
    /// The top file, as its caller named it (relative names in included files are looked up
    /// in its directory, as Mitsuba's resolver does).
    top: String,
}

impl<'r> Reader<'r> {
    pub fn new(res: &'r mut dyn Resolver, limits: Limits, defines: &[(String, String)]) -> Self {
        Self {
            res,
            limits,
            vars: HashMap::new(),
            defines: defines.iter().cloned().collect(),
            open: Vec::new(),
            files: 0,
            ids: Rc::new(HashMap::new()),
            version: (3, 0),
            search: Vec::new(),
            aliases: Vec::new(),
            top: String::new(),
        }
    }

    /// The file `name` that `el` (in `el.file`) refers to, and its bytes: looked up as Mitsuba's
    /// file resolver does, in the `<path>` directories (the latest first), then in the top
    /// file's directory (where Mitsuba finds what an included file names), then beside the
    /// file `el` is in; an absolute name as it is. Counts against the file limit.
    ///
    /// # Errors
    /// Too many files, or none of the candidates can be read (the message names them).
    pub fn resource(&mut self, el: &El, name: &str) -> Result<(String, Vec<u8>), FormatError> {
        self.files += 1;
        if self.files > self.limits.files {
            return Err(el.err(format!("more than {} files read", self.limits.files)));
        }
        let default = relative_to(&el.file, name);
        let mut candidates: Vec<String> = if name.starts_with('/') {
            Vec::new()
        } else {
            self.search
                .iter()
                .map(|dir| format!("{}/{name}", dir.trim_end_matches('/')))
                .collect()
        };
        let main = relative_to(&self.top, name);
        if !self.top.is_empty() && main != default && !candidates.contains(&main) {
            candidates.push(main);
        }
        candidates.push(default.clone());
        for c in &candidates[..candidates.len() - 1] {
            if let Ok(b) = self.res.read(c) {
                return Ok((c.clone(), b));
            }
        }
        match self.res.read(&default) {
            Ok(b) => Ok((default, b)),
            Err(e) if candidates.len() > 1 => Err(el.err(format!(
                "{default:?}: {e} (also looked in the <path> directories and the scene's \
                 directory: {})",
                candidates[..candidates.len() - 1].join(", ")
            ))),
            Err(e) => Err(el.err(format!("{default:?}: {e}"))),
        }
    }

    /// Read `file`, which must hold `<scene version=...>`.
    pub fn read_root(&mut self, file: &str, bytes: &[u8]) -> Result<El, FormatError> {
        self.top = file.to_string();
        let root = self.read_file(file, bytes, 0, true)?;
        let mut ids = HashMap::new();
        index(&root, &mut ids, true)?;
        // `<alias id="a" as="b"/>`: the object `a` is also `b` (Mitsuba 3), in file order, so an
        // alias may name an earlier alias.
        for al in std::mem::take(&mut self.aliases) {
            let (Some(id), Some(to)) = (al.attr("id"), al.attr("as")) else {
                return Err(al.err("needs id and as"));
            };
            let target = ids
                .get(id)
                .cloned()
                .ok_or_else(|| al.err(format!("aliases undefined id {id:?}")))?;
            if ids.contains_key(to) {
                return Err(al.err(format!("alias {to:?} is already an id")));
            }
            ids.insert(to.to_string(), target);
        }
        self.ids = Rc::new(ids);
        Ok(root)
    }

    fn read_file(
        &mut self,
        file: &str,
        bytes: &[u8],
        depth: usize,
        top: bool,
    ) -> Result<El, FormatError> {
        let text = crate::formats::text(file, bytes)?;
        let doc = roxmltree::Document::parse(text).map_err(|e| {
            let p = e.pos();
            FormatError {
                file: file.to_string(),
                line: p.row as usize,
                column: p.col as usize,
                message: format!("malformed XML: {e}"),
            }
        })?;
        let root = doc.root_element();
        let f: Rc<str> = Rc::from(file);
        let pos = doc.text_pos_at(root.range().start);
        let here = |msg: String| FormatError {
            file: file.to_string(),
            line: pos.row as usize,
            column: pos.col as usize,
            message: msg,
        };
        if root.tag_name().name() != "scene" {
            return Err(here(format!(
                "the root element is <{}>, not <scene>",
                root.tag_name().name()
            )));
        }
        let version = root
            .attribute("version")
            .ok_or_else(|| here("<scene> needs a version attribute".into()))?;
        let v = parse_version(version)
            .ok_or_else(|| here(format!("<scene>: bad version {version:?}")))?;
        if top {
            self.version = v;
        }
        self.open.push(file.to_string());
        let el = self.element(&doc, root, &f, depth)?;
        self.open.pop();
        Ok(el)
    }

    fn element(
        &mut self,
        doc: &roxmltree::Document,
        n: roxmltree::Node,
        file: &Rc<str>,
        depth: usize,
    ) -> Result<El, FormatError> {
        let pos = doc.text_pos_at(n.range().start);
        let old = self.version.0 < 3;
        let mut tag = n.tag_name().name().to_string();
        if old && tag == "lookAt" {
            tag = "lookat".into();
        }
        let mut el = El {
            tag,
            attrs: Vec::new(),
            children: Vec::new(),
            file: file.clone(),
            line: pos.row as usize,
            column: pos.col as usize,
        };
        for a in n.attributes() {
            let value = self.substitute(&el, a.value())?;
            let value = if old && a.name() == "name" {
                snake(&value)
            } else {
                value
            };
            el.attrs.push((a.name().to_string(), value));
        }
        for c in n.children().filter(roxmltree::Node::is_element) {
            let child = self.element(doc, c, file, depth)?;
            match child.tag.as_str() {
                "default" => {
                    let (Some(k), Some(v)) = (child.attr("name"), child.attr("value")) else {
                        return Err(child.err("needs name and value"));
                    };
                    if !self.defines.contains_key(k) {
                        self.vars.insert(k.to_string(), v.to_string());
                    }
                }
                "include" => {
                    let inc = self.include(&child, depth)?;
                    el.children.extend(inc.children);
                }
                "path" => self.search_path(&child, file)?,
                "alias" => self.aliases.push(child),
                _ => el.children.push(child),
            }
        }
        Ok(el)
    }

    /// The file `<include>` element `child` names, read at `depth + 1` (its scene's children
    /// take the element's place); a cycle or too deep a nesting is an error.
    fn include(&mut self, child: &El, depth: usize) -> Result<El, FormatError> {
        let name = child
            .attr("filename")
            .ok_or_else(|| child.err("needs a filename"))?;
        if depth + 1 > self.limits.include_depth {
            return Err(child.err(format!(
                "nested deeper than {} files",
                self.limits.include_depth
            )));
        }
        let cycle = |open: &[String], path: &str| {
            open.iter()
                .any(|o| o == path)
                .then(|| child.err(format!("include cycle ({} -> {path})", open.join(" -> "))))
        };
        // Without <path> directories the file is known before it is read when
        // it is open: the top file's directory comes first (and is the file's
        // own in the top file).
        if self.search.is_empty()
            && let Some(e) = cycle(&self.open, &relative_to(&self.top, name))
        {
            return Err(e);
        }
        let (path, bytes) = self.resource(child, name)?;
        if let Some(e) = cycle(&self.open, &path) {
            return Err(e);
        }
        self.read_file(&path, &bytes, depth + 1, false)
    }

    /// `<path value>`, a directory searched first from now on (relative to `file`).
    fn search_path(&mut self, child: &El, file: &str) -> Result<(), FormatError> {
        let dir = child
            .attr("value")
            .ok_or_else(|| child.err("needs a value"))?;
        let at = relative_to(file, dir);
        // Mitsuba refuses a search path that does not exist.
        if self.res.is_dir(&at) == Some(false) {
            return Err(child.err(format!("{at:?} is not a directory")));
        }
        self.search.insert(0, at);
        Ok(())
    }

    /// `$name` replaced by its value (`-D` first, then `<default>`); an unknown one is an error.
    fn substitute(&self, el: &El, v: &str) -> Result<String, FormatError> {
        if !v.contains('$') {
            return Ok(v.to_string());
        }
        let mut out = String::new();
        let mut rest = v;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let n = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            let name = &after[..n];
            let val = self
                .defines
                .get(name)
                .or_else(|| self.vars.get(name))
                .ok_or_else(|| {
                    el.err(format!(
                        "${name} has no value: give it a <default> or -D {name}=VALUE"
                    ))
                })?;
            out.push_str(val);
            rest = &after[n..];
        }
        out.push_str(rest);
        Ok(out)
    }
}

fn parse_version(v: &str) -> Option<(u32, u32)> {
    let mut it = v.split('.');
    let major = it.next()?.parse().ok()?;
    let minor = it.next().map_or(Some(0), |m| m.parse().ok())?;
    Some((major, minor))
}

/// `camelCase` -> `camel_case` (`intIOR` -> `int_ior`, `toWorld` -> `to_world`).
#[must_use]
pub fn snake(s: &str) -> String {
    let mut out = String::new();
    let mut prev_lower = false;
    for c in s.chars() {
        if c.is_ascii_uppercase() && prev_lower {
            out.push('_');
        }
        prev_lower = c.is_ascii_lowercase() || c.is_ascii_digit();
        out.push(c.to_ascii_lowercase());
    }
    out
}

/// Index objects with an `id`; duplicates are an error.
fn index(el: &El, ids: &mut HashMap<String, El>, root: bool) -> Result<(), FormatError> {
    if !root
        && el.tag != "ref"
        && let Some(id) = el.attr("id")
    {
        if let Some(first) = ids.get(id) {
            return Err(el.err(format!(
                "duplicate id {id:?} (first at {}:{})",
                first.line, first.column
            )));
        }
        ids.insert(id.to_string(), el.clone());
    }
    for c in &el.children {
        index(c, ids, false)?;
    }
    Ok(())
}
