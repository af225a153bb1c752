"""``sporadic.Plant``: a plant with its sampling, held as the text of a plant file.

Every plant, from numpy matrices or from a TOML file, is validated by the Rust core's plant-file
reader (the one the CLI uses), so errors name the offending field as ``sporadic design`` would.
"""

from __future__ import annotations

import math
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import _native
from ._errors import PlantError, translate


def _call(fn, *args, **kwargs):
    try:
        return fn(*args, **kwargs)
    except _native.NativeError as e:
        raise translate(e) from None


def _num(x: float) -> str:
    x = float(x)
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)  # shortest round-trip form: the core reads back the same double


def _as_matrix(field: str, m: Any) -> np.ndarray:
    try:
        a = np.asarray(m, dtype=float)
    except (TypeError, ValueError) as e:
        raise PlantError(f"{field}: not a numeric matrix ({e})", "plant_file",
                         {"field": field, "line": 0, "path": "", "reason": f"not a numeric matrix ({e})"}) from None
    if a.ndim == 0:
        a = a.reshape(1, 1)
    elif a.ndim == 1:
        a = a.reshape(1, -1)
    elif a.ndim != 2:
        raise PlantError(f"{field}: expected a 2-D matrix, got {a.ndim} dimensions", "plant_file",
                         {"field": field, "line": 0, "path": "", "reason": f"expected a 2-D matrix, got {a.ndim} dimensions"})
    return a


def _as_vector(field: str, v: Any) -> np.ndarray:
    try:
        a = np.asarray(v, dtype=float).reshape(-1)
    except (TypeError, ValueError) as e:
        raise PlantError(f"{field}: not a numeric vector ({e})", "plant_file",
                         {"field": field, "line": 0, "path": "", "reason": f"not a numeric vector ({e})"}) from None
    return a


def _toml_string(text: str) -> str:
    """A TOML basic string (escapes quotes, backslashes and control characters)."""
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04X}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _rows(a: np.ndarray) -> str:
    return "[" + ", ".join("[" + ", ".join(_num(v) for v in row) + "]" for row in a) + "]"


def _vec(a: np.ndarray) -> str:
    return "[" + ", ".join(_num(v) for v in a) + "]"


class Plant:
    """A plant ``ẋ = Ax + Bu (+ Gφ(Hx))``, ``y = Cx`` with its sampling.

    ``Plant(A, B, C, window=(T1, T2))`` — all outputs sampled at once with intervals in
    ``[T1, T2]``; ``sensors=[(C1, (T1, T2)), (C2, (T1, T2)), ...]`` — outputs polled
    round-robin, each with its own window (C may then be None). ``lipschitz`` is a dict with
    ``G``, ``H``, ``jacobian_lower``, ``jacobian_upper``; ``bounds`` a dict with
    ``disturbance`` and/or ``noise``. ``B`` may be None. Matrices are anything
    ``numpy.asarray`` accepts (a 1-D array is one row).

    Raises :class:`sporadic.PlantError` (``field``, ``reason``) for invalid data.
    """

    def __init__(
        self,
        A: Any,
        B: Any = None,
        C: Any = None,
        *,
        window: Optional[Sequence[float]] = None,
        sensors: Optional[Sequence[Any]] = None,
        lipschitz: Optional[Dict[str, Any]] = None,
        bounds: Optional[Dict[str, Any]] = None,
        name: str = "plant",
    ):
        lines = [f"name = {_toml_string(str(name))}", "", "[plant]", f"A = {_rows(_as_matrix('plant.A', A))}"]
        if B is not None:
            b = _as_matrix("plant.B", B)
            if b.size:  # an n×0 B (python-control without inputs) is no input
                lines.append(f"B = {_rows(b)}")
        if C is not None:
            lines.append(f"C = {_rows(_as_matrix('plant.C', C))}")
        if window is not None:
            lines += ["", "[sampling]", f"window = {_vec(_as_vector('sampling.window', window))}"]
        for k, s in enumerate(sensors or []):
            if isinstance(s, dict):
                c, w = s.get("C"), s.get("window")
            else:
                try:
                    c, w = s
                except (TypeError, ValueError):
                    raise PlantError(f"sensors[{k}]: expected (C, (T1, T2)) or a dict with C and window", "plant_file",
                                     {"field": f"sensors[{k}]", "line": 0, "path": "", "reason": "expected (C, (T1, T2))"}) from None
            lines += ["", "[[sensors]]", f"C = {_rows(_as_matrix(f'sensors[{k}].C', c))}",
                      f"window = {_vec(_as_vector(f'sensors[{k}].window', w))}"]
        if lipschitz is not None:
            lines += ["", "[lipschitz]"]
            for key in ("G", "H", "jacobian_lower", "jacobian_upper"):
                if key not in lipschitz:
                    raise PlantError(f"lipschitz.{key}: missing", "plant_file",
                                     {"field": f"lipschitz.{key}", "line": 0, "path": "", "reason": "missing"})
                lines.append(f"{key} = {_rows(_as_matrix(f'lipschitz.{key}', lipschitz[key]))}")
        if bounds is not None:
            lines += ["", "[bounds]"]
            for key in ("disturbance", "noise"):
                if bounds.get(key) is not None:
                    lines.append(f"{key} = {_vec(_as_vector(f'bounds.{key}', bounds[key]))}")
        try:
            self._init("\n".join(lines) + "\n", "<Plant>")
        except PlantError as e:
            # The text is generated here: its line numbers mean nothing to the caller, whose
            # arrays the field names (``plant.C``, ``sampling.window``) already point to.
            d = dict(e.details, line=0, path="")
            raise PlantError(f"{d.get('field', '')}: {d.get('reason', e.message)}", e.kind, d) from None

    def _init(self, text: str, path: str) -> None:
        self._text = text
        self._path = path
        d = _call(_native.parse_plant, text, path)
        self._data = d

    @classmethod
    def from_toml(cls, path: "str | os.PathLike[str]") -> "Plant":
        """Reads a plant file (the TOML of ``sporadic init`` and ``examples/``)."""
        p = os.fspath(path)
        try:
            with open(p, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise PlantError(f"{p}: file: {e.strerror or e}", "plant_file",
                             {"field": "file", "line": 0, "path": p, "reason": str(e.strerror or e)}) from None
        return cls.from_toml_string(text, path=p)

    @classmethod
    def from_toml_string(cls, text: str, path: str = "<string>") -> "Plant":
        """A plant from the text of a plant file (``path`` only names it in messages)."""
        self = cls.__new__(cls)
        self._init(text, path)
        return self

    @classmethod
    def from_statespace(cls, sys: Any, window: Optional[Sequence[float]] = None, **kwargs: Any) -> "Plant":
        """A plant from any object with ``A``, ``B``, ``C`` attributes (python-control's
        ``StateSpace``; ``D`` is ignored: the observers use ``y = Cx``). Keyword arguments as
        for :class:`Plant` (``window``, ``sensors``, ``lipschitz``, ``bounds``, ``name``).
        A discrete-time system (``dt`` not 0/None) is rejected."""
        for attr in ("A", "B", "C"):
            if not hasattr(sys, attr):
                raise PlantError(f"from_statespace: the system has no attribute {attr!r}", "plant_file",
                                 {"field": f"plant.{attr}", "line": 0, "path": "", "reason": f"no attribute {attr!r}"})
        dt = getattr(sys, "dt", 0)
        if dt not in (0, None) and dt is not False:
            raise PlantError(f"from_statespace: a continuous-time system is needed, got dt = {dt}", "plant_file",
                             {"field": "plant", "line": 0, "path": "", "reason": "discrete-time system"})
        kwargs.setdefault("name", getattr(sys, "name", None) or "plant")
        return cls(np.asarray(sys.A), np.asarray(sys.B), np.asarray(sys.C), window=window, **kwargs)

    # ---- data -------------------------------------------------------------------------------
    @property
    def name(self) -> str:
        return self._data["name"]

    @property
    def A(self) -> np.ndarray:
        return np.asarray(self._data["A"], dtype=float)

    @property
    def B(self) -> Optional[np.ndarray]:
        b = self._data["B"]
        return None if b is None else np.asarray(b, dtype=float).reshape(len(b), -1)

    @property
    def C(self) -> Optional[np.ndarray]:
        c = self._data["C"]
        return None if c is None else np.asarray(c, dtype=float).reshape(len(c), -1)

    @property
    def window(self) -> Optional[Tuple[float, float]]:
        w = self._data["window"]
        return None if w is None else tuple(w)

    @property
    def sensors(self) -> List[Tuple[np.ndarray, Tuple[float, float]]]:
        return [(np.asarray(c, dtype=float).reshape(len(c), -1), tuple(w)) for c, w in self._data["sensors"]]

    @property
    def lipschitz(self) -> Optional[Dict[str, np.ndarray]]:
        l = self._data["lipschitz"]
        return None if l is None else {k: np.asarray(v, dtype=float) for k, v in l.items()}

    @property
    def bounds(self) -> Optional[Dict[str, np.ndarray]]:
        b = self._data["bounds"]
        return None if b is None else {k: np.asarray(v, dtype=float) for k, v in b.items()}

    @property
    def n(self) -> int:
        return len(self._data["A"])

    def to_toml(self) -> str:
        """The plant-file text this plant is (for ``sporadic design FILE`` on the command line)."""
        return self._text

    def __repr__(self) -> str:
        return f"Plant(name={self.name!r}, n={self.n}, window={self.window!r}, sensors={len(self._data['sensors'])})"
