"""Building and editing a model by names (the methods of ``flexmbd.Model``).

Every method edits the model's document (the same document the TOML and SPACAR readers
produce; keys as in docs/model-format.md) and is checked when the model is next built, i.e.
when an analysis or a property of the compiled model asks for it. Names and the form of every
value are checked at once; an error is a ``ModelError`` whose ``item`` names the node,
element, material, section or path.
"""

import json as _json

from ._errors import ModelError

_SHAPES = {
    "rectangle": ("w", "t"),
    "circle": ("d",),
    "tube": ("d_out", "d_in"),
    "general": ("A", "Iy", "Iz", "J", "k"),
}
_DOFS = ("x", "y", "z", "rx", "ry", "rz")


def _error(message, item):
    e = ModelError(message)
    e.item = item
    return e


def _plain(value):
    """A value as plain Python (NumPy arrays and scalars become lists and numbers)."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    return value


def _vector(value, what, item):
    try:
        v = [float(x) for x in _plain(value)]
    except (TypeError, ValueError):
        raise _error(f"{what}: expected 3 numbers, found {value!r}", item) from None
    if len(v) != 3:
        raise _error(f"{what}: expected 3 numbers, found {len(v)}", item)
    return v


def _names(value, what, item):
    if isinstance(value, str):
        return [value]
    try:
        return [str(v) for v in value]
    except TypeError:
        raise _error(f"{what}: expected names, found {value!r}", item) from None


def _modes(value):
    return [int(m) for m in _plain(value)]


def _dofs(dofs, item):
    """``None`` or "all": every degree of freedom of the node; else names like "x", "rz"."""
    if dofs is None or dofs == "all":
        return None
    out = _names(dofs, "dofs", item)
    for d in out:
        if d not in _DOFS:
            raise _error(
                f"node `{item}`: unknown degree of freedom `{d}` (one of {', '.join(_DOFS)}, or None for all)",
                item,
            )
    return out


def _stroke_target(target, dof_or_mode):
    if isinstance(dof_or_mode, str):
        return {"node": target, "dof": dof_or_mode}
    return {"element": target, "mode": int(dof_or_mode)}


class _Editing:
    """The building and editing methods of ``flexmbd.Model`` (see docs/python.md)."""

    __slots__ = ()

    def _document(self):
        raise NotImplementedError

    def _add(self, kind, name, item, replace=False):
        doc = self._document()
        text = _json.dumps(item)
        if replace:
            doc.replace(kind, name, text)
        else:
            doc.add(kind, name, text)

    # -- nodes and elements --------------------------------------------------------------

    def add_node(self, name, xyz=(0.0, 0.0, 0.0), rot=False, *, at=None, replace=False):
        """Add node ``name`` at ``xyz`` [m]; ``rot=True`` gives it rotation coordinates.

        ``at="host"`` places it at the position of a node defined before it, with its own
        rotation (the second node of a hinge). ``replace=True`` replaces the node of that
        name in its place.
        """
        name = str(name)
        if at is not None:
            item = {"id": name, "at": str(at)}
        else:
            x = _vector(xyz, f"node `{name}`: xyz", name)
            item = {"id": name, "x": x[0], "y": x[1], "z": x[2], "rot": bool(rot)}
        self._add("node", name, item, replace)

    def _element(self, name, nodes, kind, data, free, input, replace, damping=None):
        name = str(name)
        item = {
            "id": name,
            "nodes": _names(nodes, f"element `{name}`: nodes", name),
            "type": kind,
            "free": _modes(free),
            "input": _modes(input),
        }
        if damping is not None:
            item["damping"] = float(damping)
        item.update({k: _plain(v) for k, v in data.items() if v is not None})
        self._add("element", name, item, replace)

    def add_truss(self, name, nodes, ea, *, free=(), input=(), damping=None, replace=False):
        """Add a truss between two nodes with axial stiffness ``ea`` = EA [N]; ``damping``: the
        retardation time tau [s] of its material damping in a time simulation."""
        self._element(name, nodes, "truss", {"EA": float(ea)}, free, input, replace, damping)

    def add_beam(
        self,
        name,
        nodes,
        *,
        section=None,
        material=None,
        orient=None,
        segments=None,
        ct=None,
        ea=None,
        gj=None,
        eiy=None,
        eiz=None,
        rho_a=None,
        free=(),
        input=(),
        fixed=(),
        damping=None,
        replace=False,
    ):
        """Add a spatial beam between two nodes (docs/statics.md).

        Its constants come from ``section=`` and ``material=`` (names of ``add_section`` and
        ``add_material``), or are given directly: ``ea`` EA [N], ``gj`` GJ [N m^2], ``eiy``,
        ``eiz`` EIy, EIz [N m^2] (a missing one 0) and ``rho_a`` the mass per length [kg/m].
        ``orient``: the local y axis (default SPACAR's rule); ``segments``: split into that
        many elements (``name:1`` ...); ``ct``: torsion-elongation coupling [m^2].
        ``free``, ``input``: released and input deformation modes (1-based); ``fixed``:
        modes rigid in statics. ``damping``: the retardation time tau [s] of its material
        damping in a time simulation (sigma = S (e + tau de/dt); over the material's).
        """
        data = {
            "section": section,
            "material": material,
            "orient": None if orient is None else _vector(orient, f"beam `{name}`: orient", name),
            "segments": None if segments is None else int(segments),
            "ct": ct,
            "EA": ea,
            "GJ": gj,
            "EIy": eiy,
            "EIz": eiz,
            "rho_a": rho_a,
            "fixed": _modes(fixed),
        }
        self._element(name, nodes, "beam", data, free, input, replace, damping)

    def add_hinge(
        self, name, nodes, axis, k=0.0, *, free=(), input=(), damping=None, replace=False
    ):
        """Add a hinge between two rotational nodes about ``axis`` (need not be unit), with a
        torsion spring ``k`` [N m/rad] on its mode 1; ``damping``: the retardation time tau [s]
        of the spring's damping in a time simulation."""
        data = {"axis": _vector(axis, f"hinge `{name}`: axis", name), "k": float(k)}
        self._element(name, nodes, "hinge", data, free, input, replace, damping)

    def add_rigid(self, name, nodes, *, replace=False):
        """Add a rigid body on ``nodes`` (the first one a rotational reference node)."""
        self._element(name, nodes, "rigid", {}, (), (), replace)

    def input_deformation(self, element, modes):
        """Make deformation ``modes`` (1-based) of ``element`` inputs (generalised
        deformations), added to those it has."""
        path = f"elements.{element}.input"
        have = self.get(path)
        self.set(path, have + [m for m in _modes(modes) if m not in have])

    def remove_node(self, name):
        """Remove a node (elements and entries on it stay and fail the build until they go)."""
        self._document().remove("node", str(name))

    def remove_element(self, name):
        """Remove an element."""
        self._document().remove("element", str(name))

    # -- materials and sections ----------------------------------------------------------

    def add_material(self, name, *, E, nu=None, G=None, rho=0.0, damping=None, replace=False):
        """Add a material: Young's modulus ``E`` [Pa], Poisson's ratio ``nu`` or shear modulus
        ``G`` [Pa], density ``rho`` [kg/m^3], ``damping`` the retardation time tau [s] of its
        material damping (Kelvin-Voigt) in a time simulation."""
        item = {"id": str(name), "E": float(E), "rho": float(rho)}
        if damping is not None:
            item["damping"] = float(damping)
        if nu is not None:
            item["nu"] = float(nu)
        if G is not None:
            item["G"] = float(G)
        self._add("material", str(name), item, replace)

    def add_section(self, name, shape="rectangle", *, shear=True, replace=False, **dims):
        """Add a cross-section [m]: ``shape="rectangle"`` (``w`` width along local y, ``t``
        thickness along local z), ``"circle"`` (``d``), ``"tube"`` (``d_out``, ``d_in``) or
        ``"general"`` (``A``, ``Iy``, ``Iz``, ``J``, shear factor ``k``). ``shear=False``: no
        shear flexibility (Euler-Bernoulli)."""
        name = str(name)
        keys = _SHAPES.get(shape)
        if keys is None:
            raise _error(
                f"section `{name}`: unknown shape `{shape}` (one of {', '.join(_SHAPES)})", name
            )
        unknown = [k for k in dims if k not in keys]
        if unknown:
            raise _error(
                f"section `{name}`: a {shape} has no `{unknown[0]}` (its dimensions: {', '.join(keys)})",
                name,
            )
        item = {"id": name, "shape": shape, "shear": bool(shear)}
        item.update({k: float(v) for k, v in dims.items()})
        self._add("section", name, item, replace)

    def remove_material(self, name):
        """Remove a material."""
        self._document().remove("material", str(name))

    def remove_section(self, name):
        """Remove a section."""
        self._document().remove("section", str(name))

    # -- supports, inputs, loads, masses, strokes ----------------------------------------

    def _put(self, kind, node, item):
        self._document().put(kind, str(node), _json.dumps(item))

    def fix(self, node, dofs=None):
        """Fix degrees of freedom of ``node``: ``None`` (or "all") every one it has, else
        names such as ``["x", "y", "rz"]``. Replaces the node's support."""
        self._put("fix", node, {"node": str(node), "dofs": _dofs(dofs, str(node))})

    def add_input(self, node, dofs=None):
        """Make degrees of freedom of ``node`` inputs (generalised coordinates): ``None``
        every one it has, else names. Replaces the node's input entry."""
        self._put("input", node, {"node": str(node), "dofs": _dofs(dofs, str(node))})

    def add_load(self, node, force=(0.0, 0.0, 0.0), moment=(0.0, 0.0, 0.0)):
        """Add a dead load at load factor 1: ``force`` [N] and ``moment`` [N m], global axes
        (a node may carry several)."""
        node = str(node)
        item = {
            "node": node,
            "force": _vector(force, f"load on `{node}`: force", node),
            "moment": _vector(moment, f"load on `{node}`: moment", node),
        }
        self._document().add("load", node, _json.dumps(item))

    def add_mass(self, node, m):
        """Set the point mass ``m`` [kg] at ``node``."""
        self._put("mass", node, {"node": str(node), "m": float(m)})

    def add_inertia(self, node, I):  # noqa: E741 (the file's key)
        """Set the inertia tensor ``I`` = [Ixx, Ixy, Ixz, Iyy, Iyz, Izz] [kg m^2] about a
        rotational ``node`` (global axes)."""
        self._put("inertia", node, {"node": str(node), "I": [float(v) for v in _plain(I)]})

    def set_velocity(self, node, v=(0.0, 0.0, 0.0), omega=(0.0, 0.0, 0.0)):
        """Set the initial velocity ``v`` [m/s] and angular velocity ``omega`` [rad/s] of
        ``node`` (time simulation)."""
        node = str(node)
        item = {
            "node": node,
            "v": _vector(v, f"velocity of `{node}`: v", node),
            "omega": _vector(omega, f"velocity of `{node}`: omega", node),
        }
        self._put("velocity", node, item)

    def set_stroke(self, target, dof_or_mode, value):
        """Set the stroke (final value at load factor 1) of an input: ``set_stroke("c", "x",
        0.01)`` a nodal coordinate (displacement [m] or rotation angle [rad]),
        ``set_stroke("hinge", 1, 0.2)`` a deformation mode of an element."""
        item = _stroke_target(str(target), dof_or_mode)
        item["value"] = float(value)
        self._put("stroke", target, item)

    def add_freedom(self, body, translation=None, *, axis=None, point=(0.0, 0.0, 0.0), pitch=0.0):
        """State a motion the design should allow (``[[freedom]]``; ``check()`` compares the
        freedom space with it): ``add_freedom("platform", translation=(1, 0, 0))``, or
        ``add_freedom("platform", axis=(0, 1, 0), point=(0, 0, 0))`` a rotation about that axis
        (``pitch`` [m/rad], 0 a pure rotation). ``body`` names an element or node of the body;
        a body may have several."""
        body = str(body)
        if (translation is None) == (axis is None):
            raise _error(
                f"freedom of `{body}`: give exactly one of translation and axis", body
            )
        item = {"body": body}
        if translation is not None:
            item["translation"] = _vector(translation, f"freedom of `{body}`: translation", body)
        else:
            item["rotation"] = {
                "point": _vector(point, f"freedom of `{body}`: point", body),
                "axis": _vector(axis, f"freedom of `{body}`: axis", body),
                "pitch": float(pitch),
            }
        self._document().add("freedom", body, _json.dumps(item))

    def remove_freedom(self, body):
        """Remove every intended freedom of ``body`` (as named in ``add_freedom``)."""
        self._document().remove("freedom", str(body))

    def remove_fix(self, node):
        """Remove the support of ``node``."""
        self._document().remove("fix", str(node))

    def remove_input(self, node):
        """Remove the input entry of ``node``."""
        self._document().remove("input", str(node))

    def remove_loads(self, node):
        """Remove every load of ``node``."""
        self._document().remove("load", str(node))

    def remove_mass(self, node):
        """Remove the point mass of ``node``."""
        self._document().remove("mass", str(node))

    def remove_inertia(self, node):
        """Remove the inertia tensor of ``node``."""
        self._document().remove("inertia", str(node))

    def remove_velocity(self, node):
        """Remove the initial velocity of ``node``."""
        self._document().remove("velocity", str(node))

    def remove_stroke(self, target, dof_or_mode):
        """Remove the stroke of an input (as ``set_stroke``)."""
        item = _stroke_target(str(target), dof_or_mode)
        self._document().remove_stroke(str(target), _json.dumps(item))

    # -- any value by its path -----------------------------------------------------------

    def get(self, path):
        """The value at ``path``, keys as in the TOML file: ``"sections.sheet.t"``,
        ``"nodes.c.x"``, ``"elements.s1a.orient"``, ``"static.steps"``, ``"loads.tip.force.1"``,
        ``"masses.#1.m"`` (the first entry). Raises ``ModelError`` naming the path."""
        return _json.loads(self._document().get(str(path)))

    def set(self, path, value):
        """Set the value at ``path`` (as ``get``): ``model.set("sections.sheet.t", 0.2e-3)``.
        The value must have the key's type (a number, a list of numbers, a name, ...)."""
        self._document().set(str(path), _json.dumps(_plain(value)))
