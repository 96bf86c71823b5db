"""flexmbd: exact-constraint design of compliant mechanisms from Python.

Read a model (the native TOML format or a SPACAR ``.dat`` file), then run the analyses of the
``flexmbd`` command line on it, in process::

    import flexmbd
    model = flexmbd.load("examples/folded_sheet_guide_5.toml")
    c = model.check()              # Dcc, its SVD, Table 1 class, motions, self-stresses, advice
    s = model.static(steps=20)     # nonlinear statics: states per load step, reactions, ...
    m = model.modes(count=6)       # natural frequencies and mode shapes about the static state
    ss = model.state_space(inputs=["p:y"], outputs=["p:y"])   # A, B, C, D
    sim = model.simulate(t_end=1.0)                            # time simulation

Results hold NumPy arrays, and ``to_dict()`` gives the document of the command's ``--json``.
The GIL is released while an analysis runs, so threads run analyses in parallel. Errors are
the exception classes below (``ModelError`` with ``file``, ``line`` and ``item``, ...).
See docs/python.md.
"""

import json as _json
import warnings as _warnings
import os as _os

from . import _flexmbd
from ._build import _Editing
from ._errors import (
    FlexmbdError,
    FlexmbdWarning,
    ModelError,
    NumericalError,
    OptionError,
    PathStoppedError,
    ReadError,
    SimulationStoppedError,
    TooLargeError,
)
from ._flexmbd import (
    CheckResult,
    ModesResult,
    SimulationResult,
    StateSpace,
    StaticResult,
    States,
)

__version__ = _flexmbd.__version__

__all__ = [
    "load",
    "Model",
    "CheckResult",
    "StaticResult",
    "ModesResult",
    "StateSpace",
    "SimulationResult",
    "States",
    "FlexmbdError",
    "ModelError",
    "OptionError",
    "NumericalError",
    "PathStoppedError",
    "SimulationStoppedError",
    "TooLargeError",
    "ReadError",
    "FlexmbdWarning",
]


def _overrides(set):
    """``set`` (a dict, or pairs) as a list of (name, float) pairs, in order."""
    if set is None:
        return []
    items = set.items() if hasattr(set, "items") else set
    return [(str(k), float(v)) for k, v in items]


def load(path, set=None):
    """Read a model file: ``.toml`` (docs/model-format.md) or a SPACAR ``.dat`` file.

    ``set`` evaluates one member of a parametric TOML model (docs/model-format.md,
    "Parameters and expressions"), as ``--set`` on the command line: ``{"t": 0.2e-3}``
    replaces the value of the parameter ``t`` (the values that use it follow), a name with
    dots is a path of the document (``{"sections.sheet.t": 0.2e-3}``). The values used are
    ``Model.parameters``.

    The file name (as given) names the model in messages and in ``to_dict()["file"]``.
    Raises ``ModelError`` (with ``file``, ``line``, ``item``) for invalid input (a parameter
    the model does not declare, too) and ``ReadError`` for a file that cannot be read.
    """
    return Model._wrap(_flexmbd.load(_os.fspath(path), _overrides(set)))


def _from_source(text, file, format):
    """Rebuild a model read from SPACAR text (what a pickle of such a ``Model`` carries)."""
    return Model._wrap(_flexmbd.parse(text, file, format))


def _from_document(json, file, source):
    """Rebuild a model from its document (what a pickle of a ``Model`` carries)."""
    return Model._wrap(_flexmbd.Document.from_json(json, file, source))


class Model(_Editing):
    """A model: its document (nodes, elements, materials, sections, supports, inputs, loads,
    masses, strokes and the analysis settings, as a TOML model file states them) and the
    analyses on it.

    Create one with ``flexmbd.load(path)``, ``Model.from_toml(text)``, ``Model.from_dat(text)``
    or ``Model(name)`` (empty), then build or edit it by names (``add_node``, ``add_beam``,
    ``fix``, ``set("sections.sheet.t", 0.2e-3)``, ...; docs/python.md). The model is compiled
    when an analysis (or a property of the compiled model such as ``node_names``) first asks
    after an edit; errors of the document are raised then as ``ModelError`` naming the item.
    A model holds no global state and can be shared between threads; it pickles as its
    document. A model read from a SPACAR ``.dat`` file is analysed as the command line
    analyses the file until it is first edited or written (``to_toml``, ``to_dict``, ``get``,
    an ``add_*``...): from then on it is the TOML document that ``flexmbd convert`` writes of
    the file (docs/spacar-import.md), and the mapping's warnings are issued as
    ``FlexmbdWarning``.
    """

    __slots__ = ("_doc", "_dat")

    def __init__(self, name="model", *, file="<python>"):
        self._doc = _flexmbd.Document.empty(str(name), str(file))
        self._dat = None

    @classmethod
    def _wrap(cls, obj):
        m = object.__new__(cls)
        if isinstance(obj, _flexmbd.Document):
            m._doc, m._dat = obj, None
        else:
            m._doc, m._dat = None, obj
        return m

    @classmethod
    def from_toml(cls, text, file="<string>", set=None):
        """A model from TOML text (docs/model-format.md); ``file`` names it in messages;
        ``set`` overrides parameters or paths as in ``flexmbd.load``."""
        return cls._wrap(_flexmbd.parse_toml(text, file, _overrides(set)))

    @classmethod
    def from_dat(cls, text, file="<string>.dat"):
        """A model from the text of a SPACAR ``.dat`` file; ``file`` names it in messages."""
        return cls._wrap(_flexmbd.parse(text, file, "dat"))

    @property
    def _core(self):
        return self._dat if self._doc is None else self._doc.core()

    def _document(self):
        if self._doc is None:
            text, file, _format = self._dat.source()
            doc, warnings = _flexmbd.Document.from_dat(text, file)
            for w in warnings:
                _warnings.warn(w, FlexmbdWarning, stacklevel=3)
            self._doc, self._dat = doc, None
        return self._doc

    def __reduce__(self):
        if self._doc is None:
            return (_from_source, self._dat.source())
        return (_from_document, (self._doc.to_json(), self._doc.file, self._doc.source))

    def __repr__(self):
        if self._doc is None:
            name, nodes, elements = self.name, self.n_nodes, self.n_elements
        else:
            name, nodes, elements = self._doc.summary()
        return "<flexmbd.Model {!r} from {}: {} nodes, {} elements>".format(
            name, self.file, nodes, elements
        )

    def copy(self):
        """An independent copy of the model (edits of one do not change the other)."""
        if self._doc is None:
            return self
        return Model._wrap(self._doc.copy())

    def to_toml(self):
        """The model's document as a TOML model file (docs/model-format.md)."""
        return self._document().to_toml()

    def to_dict(self):
        """The model's document as a dict (the keys of the TOML format; ``get`` and ``set``
        paths walk it)."""
        return _json.loads(self._document().to_json())

    # -- what the model holds ------------------------------------------------------------

    @property
    def name(self):
        """The model's name."""
        if self._doc is None:
            return self._dat.name
        return self._doc.summary()[0]

    @property
    def parameters(self):
        """The parameters of a parametric TOML model (``[parameters]``) with the values it was
        evaluated with, in file order (``{}`` for a model without parameters)."""
        if self._doc is None:
            return {}
        return self._doc.parameters()

    @property
    def file(self):
        """The file name used in messages and reports (``"<python>"`` for a model built in
        Python)."""
        return (self._doc or self._dat).file

    @property
    def format(self):
        """``"dat"`` for a model read from a SPACAR file, else ``"toml"`` (its document)."""
        return "toml" if self._doc is not None else self._dat.format

    @property
    def source(self):
        """The text the model was read from (before any edit; ``to_toml()`` writes the
        current document), or None for a model built in Python."""
        if self._doc is None:
            return self._dat.source()[0]
        return self._doc.source

    @property
    def node_names(self):
        """Node names, in model order."""
        return self._core.node_names

    @property
    def element_names(self):
        """Element names, in model order."""
        return self._core.element_names

    @property
    def element_types(self):
        """Element types (``truss``, ``beam``, ``hinge``, ``rigid``), in model order."""
        return self._core.element_types

    @property
    def n_nodes(self):
        """Number of nodes."""
        return len(self._core.node_names)

    @property
    def n_elements(self):
        """Number of elements."""
        return len(self._core.element_names)

    @property
    def n_coordinates(self):
        """Number of nodal coordinates x (positions and Euler parameters)."""
        return self._core.n_coordinates

    @property
    def coordinate_names(self):
        """Names of the nodal coordinates (``node.x`` ... ``node.l3``)."""
        return self._core.coordinate_names

    @property
    def n_deformations(self):
        """Number of deformations e."""
        return self._core.n_deformations

    @property
    def warnings(self):
        """Warnings of reading the file (``file:line: message``)."""
        return self._core.warnings

    # -- analyses ------------------------------------------------------------------------

    def check(self, *, rank_tol=None, auto=False, max_suggestions=6, method="auto"):
        """Kinematic analysis (``flexmbd check``): Dcc, its SVD, the Table 1 class, the
        motions and self-stresses, and verified repair advice.

        rank_tol: relative rank tolerance, s_i counts as zero when s_i <= rank_tol * s_1
            (default sqrt(eps)).
        auto: choose the generalised coordinates automatically (one per motion).
        max_suggestions: the most verified suggestions per motion or self-stress state.
        method: "auto" (the sparse rank-revealing LU when Dcc has more than 2500 rows or
            columns or the dense SVD would not fit in memory), "dense" or "sparse".
        Returns a ``CheckResult``.
        """
        return _flexmbd.check(self._core, rank_tol, auto, max_suggestions, method)

    def static(
        self,
        *,
        steps=None,
        compliance=(),
        buckling=None,
        tol_force=None,
        tol_disp=None,
        line_search=False,
        path=None,
        tangent_eigenvalues=False,
    ):
        """Nonlinear statics (``flexmbd static``) over load steps or by arc length.

        steps: number of load steps (over the model's [static] steps; default 10).
        compliance: node names whose 6 x 6 compliance is reported at every step (added to the
            model's [static] compliance).
        buckling: number of buckling load multipliers per step (0: none).
        tol_force, tol_disp: relative residual and increment tolerances (default 1e-9).
        line_search: backtracking line search in Newton.
        path: "load-steps" or "arc-length" (over the model's [static] path).
        tangent_eigenvalues: the smallest eigenvalues of the tangent stiffness at every step
            (``StaticResult.tangent_eigenvalues``); above 300 reduced coordinates the three
            nearest zero.
        Returns a ``StaticResult``; a path that stops part-way raises ``PathStoppedError``
        whose ``result`` holds the converged steps.
        """
        return _flexmbd.static_(
            self._core,
            steps,
            list(compliance),
            buckling,
            tol_force,
            tol_disp,
            line_search,
            path,
            tangent_eigenvalues,
        )

    def modes(self, *, count=10, at_step=None, steps=None, solver="auto", path=None):
        """Natural frequencies and mode shapes (``flexmbd modes``), linearised about a static
        equilibrium (with pre-stress) of the model's loads and strokes.

        count: number of modes.
        at_step: the load step of the static solution to linearise at (default: the last).
        steps: number of load steps of the static solution.
        solver: "auto", "dense" (all modes of the dense matrices) or "sparse" (the lowest
            modes by shift-invert Lanczos).
        path: "load-steps" or "arc-length".
        Returns a ``ModesResult``.
        """
        return _flexmbd.modes(self._core, count, at_step, steps, solver, path)

    def state_space(
        self,
        inputs,
        outputs,
        *,
        damping=0.01,
        modes=None,
        static_correction=False,
        at_step=None,
        steps=None,
        solver="auto",
    ):
        """The linear state-space model A, B, C, D (``flexmbd statespace``) about a static
        equilibrium.

        inputs: "NODE:DIR[:force|moment|motion]" or "ELEMENT:MODE:motion", DIR one of x, y,
            z, rx, ry, rz (forces and moments first in the columns of B, then motions).
        outputs: "NODE:DIR[:disp|vel|acc]", "NODE:DIR:reaction" or
            "ELEMENT:MODE:def|force[:vel|acc]" (the rows of C).
        damping: modal damping ratio of every mode.
        modes: keep only the lowest N modes (default: all modes that carry mass).
        static_correction: add the static flexibility of the dropped modes to D.
        at_step, steps: the static state linearised about.
        solver: "auto", "dense" or "sparse".
        Returns a ``StateSpace``; ``to_control()`` gives a python-control ``StateSpace``.
        """
        if isinstance(inputs, str):
            inputs = [inputs]
        if isinstance(outputs, str):
            outputs = [outputs]
        return _flexmbd.state_space(
            self._core,
            list(inputs),
            list(outputs),
            damping,
            modes,
            static_correction,
            at_step,
            steps,
            solver,
        )

    def simulate(
        self,
        *,
        t_end=None,
        dt=None,
        fixed_step=False,
        rho_inf=None,
        tolerance=None,
        output_step=None,
    ):
        """Nonlinear time simulation (``flexmbd simulate``, generalised-alpha), each option
        over the model's [simulate] settings.

        t_end: end time [s]. dt: first (or fixed) step [s]. fixed_step: no step control.
        rho_inf: spectral radius at infinite frequency in [0, 1] (default 0.9).
        tolerance: (abs, rel) of the step control. output_step: output interval [s].
        Returns a ``SimulationResult``; a run that stops early raises
        ``SimulationStoppedError`` whose ``result`` holds the frames up to then.
        """
        if tolerance is not None:
            tolerance = tuple(float(v) for v in tolerance)
        return _flexmbd.simulate(
            self._core, t_end, dt, fixed_step, rho_inf, tolerance, output_step
        )
