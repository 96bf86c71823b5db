//! Editing a [`ModelSpec`] by names: add, replace and remove items, and get or set any value by
//! a path of keys (`sections.sheet.t`, `nodes.3.x`, `static.steps`), for scripts and parameter
//! studies. An edit checks names and types; values and references are checked when the spec is
//! built ([`ModelSpec::build_file`]): removing a node does not remove the elements on it.
//!
//! **Paths.** Keys separated by dots, as in the TOML file (docs/model-format.md):
//!
//! - `name`, `description`;
//! - `static.KEY`, `simulate.KEY` (`[simulate]` is created when a key of it is set);
//! - `nodes.ID.KEY`, `elements.ID.KEY`, `materials.ID.KEY`, `sections.ID.KEY`: an item by its
//!   id; a node's keys are `x`, `y`, `z` (its coordinates), `rot`, or `at`;
//! - `fix.NODE`, `inputs.NODE`, `masses.NODE`, `inertias.NODE`, `velocities.NODE`,
//!   `loads.NODE`, `prescribed.NODE` or `prescribed.ELEMENT`: an entry by its node (or element),
//!   when one entry has it;
//! - `COLLECTION.#K`: the K-th entry (1-based) of any of these lists;
//! - then keys of the item, and indices (0-based) into lists of numbers (`loads.tip.force.1`).
//!
//! A path that does not exist is an error naming the path and the keys there are.

use super::*;
use serde::de::DeserializeOwned;
use serde_json::Value;

/// An edit that cannot be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EditError {
    /// No item of that name.
    #[error("{what} `{name}` is not defined")]
    NotFound {
        /// Kind of item.
        what: &'static str,
        /// Its name.
        name: String,
    },
    /// An item of that name exists already.
    #[error("{what} `{name}` is defined already")]
    Exists {
        /// Kind of item.
        what: &'static str,
        /// Its name.
        name: String,
    },
    /// A path that does not exist, or a value of the wrong type for it.
    #[error("path `{path}`: {reason}")]
    Path {
        /// The path as given.
        path: String,
        /// Why.
        reason: String,
    },
}

/// Items with a place in the file, kept when a value of the item is set.
trait Located: Serialize + DeserializeOwned {
    fn src_mut(&mut self) -> &mut Src;
}

macro_rules! located {
    ($($t:ty),*) => {$(
        impl Located for $t {
            fn src_mut(&mut self) -> &mut Src {
                &mut self.src
            }
        }
    )*};
}
located!(
    NodeSpec,
    ElementEntrySpec,
    MaterialSpec,
    SectionSpec,
    DofEntry,
    LoadEntry,
    MassEntry,
    InertiaEntry,
    PrescribeEntry,
    VelocityEntry,
    StaticSpec,
    SimulateSpec
);

/// Add `item` to `list` unless one has its name.
fn add<T>(
    list: &mut Vec<T>,
    item: T,
    what: &'static str,
    name: impl Fn(&T) -> &str,
) -> Result<(), EditError> {
    if list.iter().any(|x| name(x) == name(&item)) {
        return Err(EditError::Exists {
            what,
            name: name(&item).into(),
        });
    }
    list.push(item);
    Ok(())
}

/// Replace the item of `list` with the name of `item`, keeping its place; the old item.
fn replace<T>(
    list: &mut [T],
    item: T,
    what: &'static str,
    name: impl Fn(&T) -> &str,
) -> Result<T, EditError> {
    match list.iter_mut().find(|x| name(x) == name(&item)) {
        Some(x) => Ok(std::mem::replace(x, item)),
        None => Err(EditError::NotFound {
            what,
            name: name(&item).into(),
        }),
    }
}

/// Remove the item named `key` from `list`.
fn remove<T>(
    list: &mut Vec<T>,
    key: &str,
    what: &'static str,
    name: impl Fn(&T) -> &str,
) -> Result<T, EditError> {
    match list.iter().position(|x| name(x) == key) {
        Some(i) => Ok(list.remove(i)),
        None => Err(EditError::NotFound {
            what,
            name: key.into(),
        }),
    }
}

/// Remove every entry of `key` from `list`; an error when there is none.
fn remove_all<T>(
    list: &mut Vec<T>,
    key: &str,
    what: &'static str,
    name: impl Fn(&T) -> &str,
) -> Result<Vec<T>, EditError> {
    let (gone, kept): (Vec<T>, Vec<T>) = std::mem::take(list)
        .into_iter()
        .partition(|x| name(x) == key);
    *list = kept;
    if gone.is_empty() {
        return Err(EditError::NotFound {
            what,
            name: key.into(),
        });
    }
    Ok(gone)
}

/// Set the entry for `node` (replacing it, or added at the end).
fn upsert<T>(list: &mut Vec<T>, node: &str, item: T, key: impl Fn(&T) -> &str) {
    match list.iter_mut().find(|x| key(x) == node) {
        Some(x) => *x = item,
        None => list.push(item),
    }
}

fn node_name(n: &NodeSpec) -> &str {
    &n.name
}
fn element_name(e: &ElementEntrySpec) -> &str {
    &e.name
}
fn material_name(m: &MaterialSpec) -> &str {
    &m.name
}
fn section_name(s: &SectionSpec) -> &str {
    &s.name
}

/// The node or element a prescribed value is on.
fn target_name(p: &PrescribeEntry) -> &str {
    match &p.target {
        PrescribeTarget::Coordinate { node, .. } => node,
        PrescribeTarget::Deformation { element, .. } => element,
    }
}

impl ModelSpec {
    /// The node named `name`.
    pub fn node(&self, name: &str) -> Option<&NodeSpec> {
        self.nodes.iter().find(|n| n.name == name)
    }
    /// The element named `name`.
    pub fn element(&self, name: &str) -> Option<&ElementEntrySpec> {
        self.elements.iter().find(|e| e.name == name)
    }
    /// Add a node; its name must be new. A node placed `at` another must come after its host.
    pub fn add_node(&mut self, node: NodeSpec) -> Result<(), EditError> {
        add(&mut self.nodes, node, "node", node_name)
    }
    /// Replace the node of the same name (in its place); returns the old one.
    pub fn replace_node(&mut self, node: NodeSpec) -> Result<NodeSpec, EditError> {
        replace(&mut self.nodes, node, "node", node_name)
    }
    /// Remove a node (elements and entries on it stay, and fail the build until they go too).
    pub fn remove_node(&mut self, name: &str) -> Result<NodeSpec, EditError> {
        remove(&mut self.nodes, name, "node", node_name)
    }
    /// Add an element; its name must be new.
    pub fn add_element(&mut self, element: ElementEntrySpec) -> Result<(), EditError> {
        add(&mut self.elements, element, "element", element_name)
    }
    /// Replace the element of the same name (in its place); returns the old one.
    pub fn replace_element(
        &mut self,
        element: ElementEntrySpec,
    ) -> Result<ElementEntrySpec, EditError> {
        replace(&mut self.elements, element, "element", element_name)
    }
    /// Remove an element.
    pub fn remove_element(&mut self, name: &str) -> Result<ElementEntrySpec, EditError> {
        remove(&mut self.elements, name, "element", element_name)
    }
    /// Add a material; its name must be new.
    pub fn add_material(&mut self, material: MaterialSpec) -> Result<(), EditError> {
        add(&mut self.materials, material, "material", material_name)
    }
    /// Replace the material of the same name; returns the old one.
    pub fn replace_material(&mut self, material: MaterialSpec) -> Result<MaterialSpec, EditError> {
        replace(&mut self.materials, material, "material", material_name)
    }
    /// Remove a material.
    pub fn remove_material(&mut self, name: &str) -> Result<MaterialSpec, EditError> {
        remove(&mut self.materials, name, "material", material_name)
    }
    /// Add a section; its name must be new.
    pub fn add_section(&mut self, section: SectionSpec) -> Result<(), EditError> {
        add(&mut self.sections, section, "section", section_name)
    }
    /// Replace the section of the same name; returns the old one.
    pub fn replace_section(&mut self, section: SectionSpec) -> Result<SectionSpec, EditError> {
        replace(&mut self.sections, section, "section", section_name)
    }
    /// Remove a section.
    pub fn remove_section(&mut self, name: &str) -> Result<SectionSpec, EditError> {
        remove(&mut self.sections, name, "section", section_name)
    }
    /// Fix `dofs` of `node` (`None`: all it has), replacing its `[fix]` entry.
    pub fn set_fix(&mut self, node: &str, dofs: Option<&[Dof]>) {
        upsert(&mut self.fix, node, DofEntry::new(node, dofs), |d| &d.node);
    }
    /// Remove the `[fix]` entry of `node`.
    pub fn remove_fix(&mut self, node: &str) -> Result<DofEntry, EditError> {
        remove(&mut self.fix, node, "fix entry", |d| &d.node)
    }
    /// Make `dofs` of `node` inputs (`None`: all it has), replacing its `[inputs]` entry.
    pub fn set_input(&mut self, node: &str, dofs: Option<&[Dof]>) {
        upsert(&mut self.inputs, node, DofEntry::new(node, dofs), |d| {
            &d.node
        });
    }
    /// Remove the `[inputs]` entry of `node`.
    pub fn remove_input(&mut self, node: &str) -> Result<DofEntry, EditError> {
        remove(&mut self.inputs, node, "inputs entry", |d| &d.node)
    }
    /// Add a load (a node may carry several).
    pub fn add_load(&mut self, load: LoadEntry) {
        self.loads.push(load);
    }
    /// Set the load of `node` at load factor 1: the node's loads are replaced by this one
    /// (constant in time).
    pub fn set_load(&mut self, node: &str, force: [f64; 3], moment: [f64; 3]) {
        self.loads.retain(|l| l.node != node);
        self.loads.push(LoadEntry {
            node: node.into(),
            force,
            moment,
            history: None,
            comments: Vec::new(),
            src: Src::default(),
        });
    }
    /// Remove every load of `node`; the removed ones.
    pub fn remove_loads(&mut self, node: &str) -> Result<Vec<LoadEntry>, EditError> {
        remove_all(&mut self.loads, node, "load on node", |l| &l.node)
    }
    /// Add an intended freedom (`[[freedom]]`; a body may have several).
    pub fn add_freedom(&mut self, freedom: FreedomEntry) {
        self.freedoms.push(freedom);
    }
    /// Remove every intended freedom of `body` (as named in its `[[freedom]]` tables).
    pub fn remove_freedoms(&mut self, body: &str) -> Result<Vec<FreedomEntry>, EditError> {
        remove_all(&mut self.freedoms, body, "freedom of body", |f| &f.body)
    }
    /// Set the point mass [kg] of `node` (replacing its `[[mass]]`).
    pub fn set_mass(&mut self, node: &str, m: f64) {
        let entry = MassEntry {
            node: node.into(),
            m,
            comments: Vec::new(),
            src: Src::default(),
        };
        upsert(&mut self.masses, node, entry, |e| &e.node);
    }
    /// Remove the point mass of `node`.
    pub fn remove_mass(&mut self, node: &str) -> Result<MassEntry, EditError> {
        remove(&mut self.masses, node, "mass on node", |e| &e.node)
    }
    /// Set the inertia tensor [Ixx, Ixy, Ixz, Iyy, Iyz, Izz] [kg·m²] of `node`.
    pub fn set_inertia(&mut self, node: &str, i: [f64; 6]) {
        let entry = InertiaEntry {
            node: node.into(),
            i,
            comments: Vec::new(),
            src: Src::default(),
        };
        upsert(&mut self.inertias, node, entry, |e| &e.node);
    }
    /// Remove the inertia tensor of `node`.
    pub fn remove_inertia(&mut self, node: &str) -> Result<InertiaEntry, EditError> {
        remove(&mut self.inertias, node, "inertia on node", |e| &e.node)
    }
    /// Set the stroke (final value) of an input: the prescribed value of `target` is replaced
    /// (its history kept) or added (constant in time).
    pub fn set_stroke(&mut self, target: PrescribeTarget, value: f64) {
        match self.prescribed.iter_mut().find(|p| p.target == target) {
            Some(p) => p.value = value,
            None => self.prescribed.push(PrescribeEntry {
                target,
                value,
                history: None,
                comments: Vec::new(),
                src: Src::default(),
            }),
        }
    }
    /// Remove the prescribed value of `target`.
    pub fn remove_stroke(&mut self, target: &PrescribeTarget) -> Result<PrescribeEntry, EditError> {
        match self.prescribed.iter().position(|p| p.target == *target) {
            Some(i) => Ok(self.prescribed.remove(i)),
            None => Err(EditError::NotFound {
                what: "prescribed value on",
                name: match target {
                    PrescribeTarget::Coordinate { node, dof } => format!("{node}.{}", dof.name()),
                    PrescribeTarget::Deformation { element, mode } => format!("{element}.{mode}"),
                },
            }),
        }
    }
    /// Set the initial velocity [m/s] and angular velocity [rad/s] of `node`.
    pub fn set_velocity(&mut self, node: &str, v: [f64; 3], omega: [f64; 3]) {
        let entry = VelocityEntry {
            node: node.into(),
            v,
            omega,
            src: Src::default(),
        };
        upsert(&mut self.velocities, node, entry, |e| &e.node);
    }
    /// Remove the initial velocity of `node`.
    pub fn remove_velocity(&mut self, node: &str) -> Result<VelocityEntry, EditError> {
        remove(&mut self.velocities, node, "velocity of node", |e| &e.node)
    }

    /// The value at `path` (see the module documentation), as JSON.
    pub fn get(&self, path: &str) -> Result<Value, EditError> {
        let mut copy = self.clone();
        copy.at_path(path, None)
    }

    /// Set the value at `path` (see the module documentation): `spec.set("sections.sheet.t",
    /// 0.2e-3)`, `spec.set("nodes.3.x", 0.1)`, `spec.set("static.steps", 20)`. The value must
    /// have the key's type (a number, a list of numbers, a string, …).
    pub fn set(&mut self, path: &str, value: impl Into<Value>) -> Result<(), EditError> {
        self.at_path(path, Some(value.into())).map(|_| ())
    }

    /// Get (`value` `None`) or set the value at `path`; returns the value there.
    fn at_path(&mut self, path: &str, value: Option<Value>) -> Result<Value, EditError> {
        let bad = |reason: String| EditError::Path {
            path: path.into(),
            reason,
        };
        let keys: Vec<&str> = path.split('.').collect();
        let (&first, rest) = keys.split_first().ok_or_else(|| bad("empty path".into()))?;
        match first {
            "name" | "description" if rest.is_empty() => {
                let mut v = match first {
                    "name" => Value::from(self.name.clone()),
                    _ => serde_json::to_value(&self.description).unwrap_or(Value::Null),
                };
                if let Some(new) = value {
                    v = new;
                    let e = |e: serde_json::Error| bad(e.to_string());
                    match first {
                        "name" => self.name = serde_json::from_value(v.clone()).map_err(e)?,
                        _ => self.description = serde_json::from_value(v.clone()).map_err(e)?,
                    }
                }
                Ok(v)
            }
            "static" => edit_item(&mut self.statics, path, rest, value),
            "parameters" => match (rest, value) {
                ([name], None) => self
                    .parameters
                    .get(*name)
                    .map(|v| Value::from(*v))
                    .ok_or_else(|| {
                        let names: Vec<&str> = self.parameters.keys().map(String::as_str).collect();
                        bad(format!(
                            "no parameter `{name}`; the parameters are: {}",
                            names.join(", ")
                        ))
                    }),
                (_, None) => Err(bad("give `parameters.NAME`".into())),
                (_, Some(_)) => Err(bad(
                    "the parameters were evaluated when the model was read: read it again with the new value (values of the spec do not follow a changed parameter)".into(),
                )),
            },
            "simulate" => {
                let mut s = self.simulate.clone().unwrap_or_default();
                let v = edit_item(&mut s, path, rest, value.clone())?;
                if value.is_some() {
                    self.simulate = Some(s);
                }
                Ok(v)
            }
            _ => {
                let (&key, rest) = rest
                    .split_first()
                    .ok_or_else(|| bad(format!("`{first}` needs the name of an item after it")))?;
                macro_rules! pick {
                    ($list:expr, $name:expr) => {{
                        let list = &mut $list;
                        let i = pick(list.iter().map($name), key).map_err(bad)?;
                        edit_item(&mut list[i], path, rest, value)
                    }};
                }
                match first {
                    "nodes" => pick!(self.nodes, node_name),
                    "elements" => pick!(self.elements, element_name),
                    "materials" => pick!(self.materials, material_name),
                    "sections" => pick!(self.sections, section_name),
                    "fix" => pick!(self.fix, |d: &DofEntry| d.node.as_str()),
                    "inputs" => pick!(self.inputs, |d: &DofEntry| d.node.as_str()),
                    "loads" => pick!(self.loads, |d: &LoadEntry| d.node.as_str()),
                    "masses" => pick!(self.masses, |d: &MassEntry| d.node.as_str()),
                    "inertias" => pick!(self.inertias, |d: &InertiaEntry| d.node.as_str()),
                    "velocities" => pick!(self.velocities, |d: &VelocityEntry| d.node.as_str()),
                    "prescribed" => pick!(self.prescribed, target_name),
                    other => Err(bad(format!(
                        "no `{other}` in a model; the first key is one of name, description, nodes, elements, materials, sections, fix, inputs, loads, masses, inertias, prescribed, velocities, static, simulate, parameters (to read)"
                    ))),
                }
            }
        }
    }
}

/// The index of the entry named `key` (unique), or `#K` (1-based).
fn pick<'a>(names: impl Iterator<Item = &'a str>, key: &str) -> Result<usize, String> {
    let names: Vec<&str> = names.collect();
    if let Some(k) = key.strip_prefix('#') {
        return match k.parse::<usize>() {
            Ok(k) if (1..=names.len()).contains(&k) => Ok(k - 1),
            _ => Err(format!(
                "`{key}`: give an entry number from #1 to #{}",
                names.len()
            )),
        };
    }
    let found: Vec<usize> = (0..names.len()).filter(|&i| names[i] == key).collect();
    match found.as_slice() {
        [i] => Ok(*i),
        [] => Err(format!("no entry `{key}`")),
        _ => Err(format!(
            "{} entries have `{key}`; give its number instead (#{})",
            found.len(),
            found[0] + 1
        )),
    }
}

/// Get or set the value at `keys` inside `item` (through its serialised form, so that the
/// keys are those of the file); the item keeps its place in the file.
fn edit_item<T: Located>(
    item: &mut T,
    path: &str,
    keys: &[&str],
    value: Option<Value>,
) -> Result<Value, EditError> {
    let bad = |reason: String| EditError::Path {
        path: path.into(),
        reason,
    };
    let mut whole = serde_json::to_value(&*item).map_err(|e| bad(e.to_string()))?;
    let mut here = &mut whole;
    for key in keys {
        here = match here {
            Value::Object(map) => {
                let known: Vec<String> = map.keys().cloned().collect();
                map.get_mut(*key).ok_or_else(|| {
                    bad(format!(
                        "no key `{key}` here; the keys are: {}",
                        known.join(", ")
                    ))
                })?
            }
            Value::Array(list) => {
                let n = list.len();
                key.parse::<usize>()
                    .ok()
                    .and_then(|i| list.get_mut(i))
                    .ok_or_else(|| match n {
                        0 => bad(format!("`{key}`: the list is empty")),
                        _ => bad(format!("`{key}`: give an index from 0 to {}", n - 1)),
                    })?
            }
            other => return Err(bad(format!("`{key}`: {other} has no keys"))),
        };
    }
    let Some(new) = value else {
        return Ok(here.clone());
    };
    *here = new.clone();
    let mut edited: T = serde_json::from_value(whole).map_err(|e| bad(e.to_string()))?;
    *edited.src_mut() = std::mem::take(item.src_mut());
    *item = edited;
    Ok(new)
}
