"""Type stubs of rocking_stones (the classes and functions live in the native module)."""

import os
from typing import Any, Callable, Dict, List, Literal, Optional, Protocol, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__version__: str
DEFAULT_COPLANAR_TOL: float
"""Default relative coplanarity tolerance of the facet merge (× bounding-box diagonal)."""
PAPER_NU: float
"""The hand experimenter's ν of the paper (0.0035)."""

class _HasMesh(Protocol):
    @property
    def vertices(self) -> Any: ...
    @property
    def faces(self) -> Any: ...

_MeshLike = Union[
    str,
    "os.PathLike[str]",
    Tuple[npt.ArrayLike, npt.ArrayLike],
    _HasMesh,
]
"""A mesh file path (STL, OBJ, PLY), a ``(vertices (n, 3), faces (m, 3))`` pair of arrays, or
any object with ``.vertices`` and ``.faces`` such as a ``trimesh.Trimesh``."""

_Counts = Tuple[int, int, int]
"""(S, U, H): stable, unstable and saddle equilibria."""

_FloatArray = npt.NDArray[np.float64]
_IntArray = npt.NDArray[np.int64]

class MeshError(ValueError):
    """The mesh is not the boundary of a solid (open, non-manifold, inconsistently oriented,
    several shells, flat, NaN, truncated or unparsable file...). ``str(e)`` is the message
    ``rocking`` prints after ``error:``, naming the file (or ``<memory>`` / ``name``)."""

@final
class Analysis:
    """The static analysis of one stone (``rocking analyze``): mass properties, exact hull,
    micro-equilibria, the ν-hierarchy N(ν), the plateau, macro counts, flocks and rocking
    equilibria. Returned by :func:`analyze`."""

    @property
    def name(self) -> str:
        """The path as given, ``<memory>``, or the ``name`` passed to :func:`analyze`."""
    @property
    def micro(self) -> _Counts:
        """Micro-scale (S, U, H): stable facets, unstable vertices, saddle edges of the hull."""
    @property
    def macro(self) -> _Counts:
        """Macro-scale (S, U, H) at :attr:`nu`."""
    @property
    def nu(self) -> float:
        """ν of the macro scale: the caller's, the middle of a clear plateau, or 0.0035."""
    @property
    def nu_source(self) -> Literal["user", "plateau", "paper-default"]:
        """Where :attr:`nu` came from."""
    @property
    def plateau(self) -> Optional[Dict[str, Any]]:
        """The plateau of n(ν): nu_lo, nu_hi, decades, counts, clarity, clear; None if none."""
    @property
    def staircase(self) -> Dict[str, npt.NDArray[Any]]:
        """N(ν) as columns ``nu_lo, nu_hi, stable, unstable, saddle, n`` (n = N/N(0)): one row
        per constant step, from ν = 0 upwards."""
    def counts_at(self, nu: float) -> _Counts:
        """(S, U, H) of the hierarchy at any ν ≥ 0."""
    @property
    def equilibria(self) -> Dict[str, npt.NDArray[Any]]:
        """Every micro-equilibrium as columns ``index, kind ('stable'|'saddle'|'unstable'),
        site ('facet'|'edge'|'vertex'), site_index, x, y, z, r, flock`` (``pd.DataFrame``-ready)."""
    @property
    def points(self) -> _FloatArray:
        """Contact points of the micro-equilibria, (n, 3), in the order of :attr:`equilibria`."""
    @property
    def flocks(self) -> List[Dict[str, Any]]:
        """Flocks at :attr:`nu`: id, type, root, members, stable, unstable, saddle."""
    @property
    def rocking(self) -> Dict[str, npt.NDArray[Any]]:
        """Rocking equilibria (stable micro-equilibria in unstable or saddle flocks) as columns
        ``index, facet, x, y, z, r, r_normalised, flock, flock_type``."""
    @property
    def shape(self) -> Dict[str, Any]:
        """Axes a ≥ b ≥ c, c_over_b, b_over_a, c_over_a, zingg, volume, area,
        isoperimetric_ratio."""
    @property
    def volume(self) -> float:
        """Volume of the solid bounded by the mesh (input units³)."""
    @property
    def area(self) -> float:
        """Surface area of the mesh."""
    @property
    def center_of_mass(self) -> _FloatArray:
        """Centre of mass G of the homogeneous solid, (3,)."""
    @property
    def inertia(self) -> _FloatArray:
        """Inertia tensor about G for density 1, (3, 3) (as trimesh's ``moment_inertia``)."""
    @property
    def principal_moments(self) -> _FloatArray:
        """Principal moments of inertia, ascending, (3,)."""
    @property
    def principal_axes(self) -> _FloatArray:
        """Principal axes as unit columns, (3, 3)."""
    @property
    def hull(self) -> Dict[str, Any]:
        """Hull summary: facets, edges, vertices, triangles, coplanar_tol, volume, area."""
    @property
    def hull_vertices(self) -> _FloatArray:
        """Vertices of the convex hull, (k, 3)."""
    @property
    def facet_normals(self) -> _FloatArray:
        """Outward unit normals of the hull facets, (f, 3), indexed by facet number."""
    @property
    def vertices(self) -> _FloatArray:
        """Vertices of the checked mesh (exact duplicates welded, unused ones dropped), (n, 3)."""
    @property
    def faces(self) -> _IntArray:
        """Triangles of the checked mesh, outward (counter-clockwise), (m, 3)."""
    @property
    def repairs(self) -> Dict[str, Any]:
        """welded_vertices, unreferenced_vertices, degenerate_triangles, flipped."""
    def to_dict(self) -> Dict[str, Any]:
        """The report; equal to ``json.loads`` of ``rocking analyze MESH --json``."""
    @property
    def open_scan(self) -> Optional[Dict[str, Any]]:
        """For an open scan (+z up, open where the rock meets its pedestal): the rim of the
        hidden base and its loops, the gaps closed, the base (``flat cap``) and how many
        micro-equilibria touch it; None for a closed stone."""
    def to_json(self, pretty: bool = True) -> str:
        """The report as JSON; ``pretty=True`` is exactly what ``rocking analyze --json``
        prints (without the final newline)."""
    def summary(self) -> str:
        """The human summary ``rocking analyze`` prints."""
    def basins(self) -> "Basins":
        """Quasi-static resting probabilities of this stone (see :func:`basins`)."""

@final
class Basins:
    """Quasi-static resting probabilities: the basin of attraction of every stable facet on the
    sphere of down directions, area / 4π, computed exactly (error ≤ :attr:`error`)."""

    @property
    def facet(self) -> _IntArray:
        """Hull facet of each stable micro-equilibrium."""
    @property
    def equilibrium(self) -> _IntArray:
        """Index of the stable micro-equilibrium (as in :attr:`Analysis.equilibria`)."""
    @property
    def flock(self) -> _IntArray:
        """Flock of the stable micro-equilibrium at :attr:`nu`."""
    @property
    def normal(self) -> _FloatArray:
        """Outward unit normal of the facet, (k, 3); at rest it points straight down."""
    @property
    def probability(self) -> _FloatArray:
        """Quasi-static probability of coming to rest on the facet (sums to 1)."""
    @property
    def flock_probability(self) -> _FloatArray:
        """Probability of every flock, indexed by flock id."""
    @property
    def error(self) -> float:
        """Bound on the absolute error of every probability."""
    @property
    def method(self) -> str: ...
    @property
    def nu(self) -> float: ...
    def to_dict(self) -> Dict[str, npt.NDArray[Any]]:
        """Columns ``facet, equilibrium, flock, nx, ny, nz, probability``."""
    def __len__(self) -> int: ...

@final
class DropResult:
    """A drop run (``rocking drop``): counts per facet and flock with 95 % Wilson intervals
    beside the quasi-static probabilities, χ² and KL, and every drop's outcome."""

    @property
    def drops(self) -> int: ...
    @property
    def seed(self) -> int: ...
    @property
    def settled(self) -> int:
        """Drops that came to rest (or were decided by the energy certificate)."""
    @property
    def unsettled(self) -> int:
        """Drops still moving at the time cap (left out of every count and fit)."""
    @property
    def deepest_penetration(self) -> float:
        """The deepest any hull corner went below the ground at any step or sub-step (R_max)."""
    @property
    def certified(self) -> int:
        """Drops ended early by the energy certificate."""
    @property
    def off_equilibrium(self) -> int:
        """Settled drops that did not end on a stable micro-equilibrium."""
    @property
    def mean_time(self) -> float:
        """Mean simulated time per drop (s of the scaled 1 m body)."""
    @property
    def nu(self) -> float: ...
    @property
    def facets(self) -> Dict[str, npt.NDArray[Any]]:
        """Columns ``facet, nx, ny, nz, equilibrium, flock (-1: not stable), count, fraction,
        ci95_lo, ci95_hi, static_probability``."""
    @property
    def flocks(self) -> Dict[str, npt.NDArray[Any]]:
        """Columns ``id, type, count, fraction, ci95_lo, ci95_hi, static_probability``."""
    @property
    def outcomes(self) -> Dict[str, npt.NDArray[Any]]:
        """Every drop: ``index, settled, facet, flock (-1: none), time, certified,
        deepest_penetration`` (R_max)."""
    @property
    def fit_facets(self) -> Optional[Dict[str, Any]]: ...
    @property
    def fit_flocks(self) -> Dict[str, Any]: ...
    def to_dict(self) -> Dict[str, Any]:
        """Equal to ``json.loads`` of ``rocking drop MESH -n N --seed S --json``."""
    def to_json(self, pretty: bool = True) -> str: ...
    def summary(self) -> str:
        """The human summary ``rocking drop`` prints."""

@final
class DynamicsResult:
    """A perturbation (``rocking perturb``) or shaking (``rocking shake``) run."""

    def to_dict(self) -> Dict[str, Any]:
        """Equal to ``json.loads`` of the CLI's ``--json`` output."""
    def to_json(self, pretty: bool = True) -> str: ...
    @property
    def trials(self) -> Dict[str, Any]:
        """Every trial as columns (nested fields joined with ``_``)."""
    def summary(self) -> str: ...
    def __getitem__(self, key: str, /) -> Any:
        """A top-level field of :meth:`to_dict`."""

@final
class Study:
    """A field study (``rocking study FOLDER``): one row per scan."""

    @property
    def rows(self) -> List[Dict[str, Any]]:
        """One dict per pebble with the columns of ``pebbles.csv`` (None for empty cells)."""
    @property
    def samples(self) -> List[Dict[str, Any]]:
        """One dict per sample with the columns of ``samples.csv``."""
    @property
    def reports(self) -> List[Optional[Dict[str, Any]]]:
        """Every pebble's ``rocking analyze --json`` report (None where it failed)."""
    @property
    def errors(self) -> List[Optional[str]]: ...
    @property
    def nu(self) -> Optional[float]:
        """ν of the one-ν hand columns; None when the two-tolerance experimenter counts them."""
    @property
    def experimenter(self) -> Optional[Dict[str, Dict[str, float]]]:
        """The two-tolerance hand experimenter: ``{"stable": {"median", "sd_log10"}, "unstable": …}``."""
    def hand(self) -> Dict[str, Any]:
        """``hand.json`` as a dict: every analysed pebble's most likely pair and distribution."""
    def hand_json(self) -> str:
        """``hand.json`` exactly as ``rocking study`` writes it."""
    def pebbles_csv(self) -> str:
        """``pebbles.csv`` exactly as ``rocking study`` writes it."""
    def samples_csv(self) -> str:
        """``samples.csv`` exactly as ``rocking study`` writes it."""
    def to_dict(self) -> Dict[str, Any]:
        """Columns of :attr:`rows` (``pd.DataFrame(study.to_dict())``)."""
    def __len__(self) -> int: ...

def analyze(
    mesh: Optional[_MeshLike] = None,
    nu: Optional[float] = None,
    coplanar_tol: float = ...,
    name: Optional[str] = None,
) -> Analysis:
    """Analyse a stone as ``rocking analyze`` does.

    ``mesh``: a path, a ``(vertices, faces)`` pair, a ``trimesh.Trimesh`` (anything with
    ``.vertices`` and ``.faces``), or None for the bundled scanned stone. In-memory meshes are
    welded and checked exactly like files; their errors name ``name`` (default ``<memory>``).
    An open scan (+z up, open where the rock meets its pedestal) is closed with a flat cap and
    the micro-equilibria touching that hidden base are marked (:attr:`Analysis.open_scan`).
    ``nu`` fixes the macro scale (default: the automatic plateau, else 0.0035);
    ``coplanar_tol`` is the relative tolerance of the facet merge (1e-6 for f32 CAD files).

    Raises :class:`MeshError` (a ``ValueError``) for unusable meshes, ``FileNotFoundError`` /
    ``OSError`` for unreadable files, ``ValueError`` for bad options.
    """

def basins(mesh: Union[_MeshLike, Analysis, None] = None, nu: Optional[float] = None, name: Optional[str] = None) -> Basins:
    """Quasi-static probability of resting on each stable facet, with its normal."""

def drop(
    mesh: Union[_MeshLike, Analysis, None] = None,
    n: int = 1000,
    seed: int = 1,
    *,
    preset: Literal["quasi-static", "drop", "throw"] = "throw",
    surface: Literal["steel-on-wood", "stone-on-stone", "rock-on-concrete", "rock-on-steel"] = "steel-on-wood",
    size: Optional[float] = None,
    length_unit: Union[str, float, None] = None,
    certificate: Literal["none", "facet", "flock"] = "facet",
    reference: bool = False,
    fast: bool = False,
    nu: Optional[float] = None,
    name: Optional[str] = None,
    threads: Optional[int] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
    **params: Union[float, str],
) -> DropResult:
    """Drop the stone ``n`` times in rapier3d, as ``rocking drop MESH -n N --seed S --preset P
    --surface S``; drop i depends only on (seed, i).

    ``preset`` (the launch protocol) and ``surface`` choose the parameters as the CLI does; the
    real size is ``size`` (R_max in metres) or ``length_unit`` ("mm", "cm", "m", "km", "in" or
    metres per unit), needed for every mesh but the bundled stone (a ``ValueError`` says so), and
    an R_max outside 2 mm–20 m is warned about. ``**params`` override single ones, as the CLI's
    options, in real units for the stone's size: height (R_max), horizontal_speed (m/s), spin
    (rad/s), spin_distribution, friction, restitution, rolling_resistance_mm,
    torsional_friction_mm (mm), linear_damping, angular_damping (1/s), dt, max_time (s),
    solver_iterations, rest_linear_speed (m/s), rest_angular_speed (rad/s), rest_time (s), flight
    (``"free"``, the default: exact landings and sub-stepped impacts, so no impact starts inside
    the ground, or ``"rapier"``: contacts found at rapier's step boundaries; the CLI's
    ``--flight``). The time step is the preset's longest stable one, 0.0261 √(R_max/g);
    ``reference=True`` is the CLI's ``--reference``: free flight at half that step, the one it is
    checked against (``**params`` still override it). ``fast=True`` (the old ``--fast``, now the default) is
    accepted so that older scripts run.
    Releases the GIL; Ctrl-C raises KeyboardInterrupt within a fraction of a second.
    ``threads``: threads of this run (default: ``RAYON_NUM_THREADS`` or all cores).
    ``progress``: ``callable(done, total)`` called about every 0.1 s (a tqdm bar's ``update``).
    """

def perturb(
    mesh: Union[_MeshLike, Analysis, None] = None,
    *,
    equilibria: Optional[Sequence[int]] = None,
    flock: Optional[int] = None,
    family: Literal["push", "spin"] = "push",
    trials: int = 40,
    seed: int = 1,
    eps_min: float = 1e-5,
    eps_max: float = 1.0,
    eps_steps: int = 16,
    epsilon_star: Optional[float] = None,
    certificate: Union[Literal["none", "facet", "flock"], bool, None] = None,
    contact_model: Optional[Literal["surface", "damped"]] = None,
    surface: Optional[Literal["stone-on-stone", "rock-on-concrete", "rock-on-steel", "steel-on-wood"]] = None,
    length_unit: Union[str, float, None] = None,
    size: Optional[float] = None,
    nu: Optional[float] = None,
    name: Optional[str] = None,
    threads: Optional[int] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
    **params: float,
) -> DynamicsResult:
    """Push or spin the stone resting on its stable micro-equilibria, as ``rocking perturb``:
    P(same), P(same flock), P(toppled) against ε = E/(m g R_max), thresholds and static barriers.
    The contact of drops and field rocks: ``contact_model`` "surface" (default) or "damped" (the
    overdamped reference), ``surface`` (default "stone-on-stone"), the real size by
    ``length_unit`` (mm, cm, m, km, in or metres per unit) or ``size`` (R_max in metres), needed
    for every mesh but the bundled stone; an R_max outside 2 mm–20 m is warned about;
    ``to_dict()`` has ``r_max_m``. ``certificate``: "none" (default), "facet" (or True) or
    "flock", as ``--certificate``. ``**params`` in real units: friction, restitution,
    rolling_resistance_mm (mm), dt, max_time (s), contact_frequency (Hz), settle_time, hold_time,
    rest_time (s), rest_linear_speed (m/s), rest_angular_speed (rad/s)."""

def shake(
    mesh: Union[_MeshLike, Analysis, None] = None,
    *,
    equilibria: Optional[Sequence[int]] = None,
    pulse: Optional[Tuple[float, float, float]] = None,
    motion: Union[str, "os.PathLike[str]", Sequence[Union[str, "os.PathLike[str]"]], None] = None,
    columns: str = "1,2",
    accel_unit: Literal["g", "m/s2", "gal"] = "g",
    pga_max: Optional[float] = None,
    pga_steps: int = 20,
    azimuth: Optional[float] = None,
    trials: int = 40,
    seed: int = 1,
    contact_model: Optional[Literal["surface", "damped"]] = None,
    surface: Optional[Literal["stone-on-stone", "rock-on-concrete", "rock-on-steel", "steel-on-wood"]] = None,
    length_unit: Union[str, float, None] = None,
    size: Optional[float] = None,
    nu: Optional[float] = None,
    name: Optional[str] = None,
    threads: Optional[int] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
    **params: float,
) -> DynamicsResult:
    """Shake the ground under the resting stone, as ``rocking shake``: fragility curves.
    ``pulse=(amplitude g, frequency Hz of the real stone, cycles)`` or ``motion=`` a CSV (read
    with ``columns``, ``accel_unit``) or 1–3 .AT2 files; ``azimuth`` degrees from the x axis of
    the stone as it stands (default: random per trial); the contact and size as for
    ``perturb``."""

def shake_rock(
    mesh: Union[_MeshLike, Analysis, None] = None,
    *,
    pose: str,
    length_unit: Union[str, float, None] = None,
    size: Optional[float] = None,
    motion: Union[str, "os.PathLike[str]", Sequence[Union[str, "os.PathLike[str]"]], None] = None,
    accel: Optional[Any] = None,
    dt: Optional[float] = None,
    columns: str = "1,2",
    accel_unit: Literal["g", "m/s2", "gal"] = "g",
    baseline: Optional[int] = None,
    azimuth: Optional[float] = None,
    surface: Literal["rock-on-concrete", "stone-on-stone", "rock-on-steel", "steel-on-wood"] = "rock-on-concrete",
    scale: float = 1.0,
    ensemble: Optional[int] = None,
    uncertainty: Optional[Dict[str, Any]] = None,
    seed: int = 1,
    nu: Optional[float] = None,
    name: Optional[str] = None,
) -> Dict[str, Any]:
    """A field rock at true size under one ground motion, as ``rocking shake --pose ... --json``:
    ``pose`` "as-scanned", "equilibrium:ID" (the index ``analyze`` prints), "facet:F" (the hull
    facet it rests on) or "quat:w,x,y,z"; ``length_unit`` or ``size`` as for ``perturb``, needed
    for every mesh but the bundled stone; ``motion`` a CSV or 1–3 .AT2 files, or ``accel`` an
    (n,) / (n, k ≤ 3) array in m/s² every ``dt`` s; ``azimuth`` degrees of the record's x axis
    from the rock's x axis as it stands (default 0). Returns overturned, max_tilt_deg, slide_m, pga_g, pgv_m_s,
    pgv_over_pga_s, ...

    ``ensemble=N`` (``--ensemble N --seed SEED``): N members drawing what ``uncertainty`` leaves
    unknown; returns the ensemble dict instead: probability {members, settled, overturned,
    p_overturn, interval95}, sensitivity [{input, measure, correlation}], tipping [...],
    members [{draw, run}], with record, scale, pga_g, ..., seed, uncertainty. ``uncertainty``
    keys (all optional): contact_tolerance_mm T or (low, high) in mm; azimuth (low, high)
    degrees or "unknown"; random_sign bool; friction, restitution (low, high);
    rolling_resistance_mm (low, high) in mm; base "drawn" (the default: every member draws the
    hidden base it stands on, ``--base drawn``; the dict then has base {members, tan_alpha,
    depth_m} and each draw its base) or "scanned" (the scan's own base); base_depth_mm T or
    (low, high), base_band_mm, base_region (low, high), rocking_points_mm ((x, y), (x, y), (x, y)). Friction, restitution and rolling
    resistance not given range over the surface pair's published ranges. The mesh may be an
    open field scan (a path or a trimesh), standing as scanned."""

def study(
    folder: Union[str, "os.PathLike[str]"],
    meta: Optional[Union[str, "os.PathLike[str]"]] = None,
    *,
    nu: Optional[float] = None,
    tolerances: Optional[Tuple[float, float, float, float]] = None,
    coplanar_tol: float = ...,
    allow_unmatched: bool = False,
    dynamic: bool = False,
    length_unit: Union[str, float, None] = None,
    trials: int = ...,
    height: float = ...,
    seed: int = 1,
    threads: Optional[int] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Study:
    """Field study over a folder of scans, as ``rocking study FOLDER --meta META``: one row per
    pebble (:attr:`Study.rows`), the columns of ``pebbles.csv``. The hand columns are the
    two-tolerance hand experimenter's most likely pair ``hand_S``, ``hand_U`` with its probability
    ``hand_p`` and the distribution ``hand_pairs`` (``tolerances=(nu_s, sd_s, nu_u, sd_u)``,
    default the calibration on Table 2 in the real scans' frame, as ``rocking study FOLDER``;
    :meth:`Study.hand` has every pebble's distribution), or
    with ``nu=`` the paper's one-ν counts ``hand_nu``, ``hand_S``, ``hand_U``, ``hand_H``.
    ``dynamic=True`` adds the simulated hand experimenter, who sets each pebble down at its real
    size: ``length_unit`` (the scans' unit) is then needed."""

def generate(
    shape: Literal[
        "tetrahedron", "cube", "octahedron", "dodecahedron", "icosahedron", "box", "ellipsoid", "noisy-box", "pebble"
    ],
    *,
    axes: Optional[Tuple[float, float, float]] = None,
    n: Optional[int] = None,
    noise: Optional[float] = None,
    roughness: Optional[float] = None,
    seed: int = 0,
) -> Tuple[_FloatArray, _IntArray]:
    """A synthetic shape as ``(vertices, faces)``, as ``rocking generate`` builds it (Platonic
    solids have circumradius 1)."""

def num_threads() -> int:
    """Threads of the long runs by default: ``RAYON_NUM_THREADS`` if set, else the cores."""
