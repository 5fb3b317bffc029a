"""gyrocomp: remove noise and temperature drift from MEMS gyro output (docs/guides/python.md).

Every function takes numpy arrays (float64, used in place when contiguous) and options as keyword
arguments named as the C++ Options fields, with the C++ defaults. Results are objects with named
attributes (units in the names, as in C++) and ``to_dict()``. Bad input or options raise
``ValueError`` with the library's message; I/O and internal failures ``RuntimeError``. Long calls
(vmd, sample_entropy, compute_allan, fit_drift_model, run_parallel_model) run with the GIL released,
accept ``cancel=CancellationToken()`` (and vmd, fit_drift_model, run_parallel_model ``progress(stage,
fraction)``), and stop within a fraction of a second on Ctrl-C (KeyboardInterrupt), on the token
(gyrocomp.Cancelled) or on a Dask cancel (gyrocomp.dask.cancel_with_task).
"""

import functools as _functools

from . import _core
from . import dask  # noqa: F401  (gyrocomp.dask.cancel_with_task; imports distributed only when used)
from ._core import CancellationToken, Cancelled, DriftModel, load_drift_model, drift_model_from_json

__version__ = _core.__version__


class Result:
    """A result: named attributes (nested results for nested parts) and to_dict()."""

    def __init__(self, name, values):
        self._name = name
        for key, value in values.items():
            setattr(self, key, _wrap(key, value))

    def to_dict(self):
        return {k: _unwrap(v) for k, v in self.__dict__.items() if not k.startswith("_")}

    def keys(self):
        return [k for k in self.__dict__ if not k.startswith("_")]

    def __getitem__(self, key):  # result["gx_dps"] as well as result.gx_dps (names that are not identifiers)
        if key.startswith("_") or key not in self.__dict__:
            raise KeyError(key)
        return self.__dict__[key]

    def __repr__(self):
        brief = getattr(self, "brief_report", None)
        return f"<gyrocomp.{self._name} {brief}>" if brief else f"<gyrocomp.{self._name}>"


def _wrap(name, value):
    if isinstance(value, dict):
        return Result(name, value)
    if isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
        return [Result(name, v) for v in value]
    return value


def _unwrap(value):
    if isinstance(value, Result):
        return value.to_dict()
    if isinstance(value, list):
        return [_unwrap(v) for v in value]
    return value


def _returns(name):
    def decorate(fn):
        @_functools.wraps(fn)
        def wrapper(*args, **kwargs):
            return Result(name, fn(*args, **kwargs))
        return wrapper
    return decorate


# DriftModel.summary as a result object too (the C++ property returns a dict).
_summary_dict = DriftModel.summary
DriftModel.summary = property(lambda self: Result("DriftFitSummary", _summary_dict.fget(self)),
                              doc="The fit summary (DriftFitSummary) as a result object.")

compute_allan = _returns("AllanResult")(_core.compute_allan)
compute_deviation = _returns("DeviationCurve")(_core.compute_deviation)
kalibr_imu_yaml = _core.kalibr_imu_yaml
imu_noise_files = _returns("ImuNoiseFiles")(_core.imu_noise_files)
simulate = _returns("SimulatedRun")(_core.simulate)
simulate_board = _returns("BoardRun")(_core.simulate_board)
vmd = _returns("VmdResult")(_core.vmd)
decompose = _returns("Decomposition")(_core.decompose)
sample_entropy = _returns("SampleEntropyResult")(_core.sample_entropy)
wavelet_denoise = _returns("WaveletDenoiseResult")(_core.wavelet_denoise)
flp_denoise = _returns("FlpResult")(_core.flp_denoise)
wflp_denoise = _returns("WflpResult")(_core.wflp_denoise)
measure_bandwidth = _returns("BandwidthResult")(_core.measure_bandwidth)
fit_drift_model = _core.fit_drift_model
run_parallel_model = _returns("PipelineResult")(_core.run_parallel_model)
compare_methods = _returns("ComparisonResult")(_core.compare_methods)
read_log = _returns("GyroLog")(_core.read_log)
read_log_rows = _returns("FlightLogTable")(_core.read_log_rows)
calibrate = _returns("CalibrateResult")(_core.calibrate)
project_onto_cubic = _returns("TemperatureCubic")(_core.project_onto_cubic)
px4_thermal_params = _core.px4_thermal_params
ardupilot_thermal_params = _core.ardupilot_thermal_params
validate_drift_model = _returns("DriftValidation")(_core.validate_drift_model)
generate_c = _returns("GeneratedC")(_core.generate_c)
plan = _returns("PlanResult")(_core.plan)
inspect = _returns("LogInventory")(_core.inspect)


def export_cubics(models, **options):
    """The cubic each axis model exports (``gyrocomp export --format px4|ardupilot``), one result per axis.

    As the CLI: every axis projected onto the temperature range the models share, or, per
    ``static_weight`` ("auto", "temperature", "time"), the calibration run's static curve with each
    temperature alike; ``calibration`` (``-i``) and ``validation`` (``--validation``) are one path
    each, read with read_log's keywords (rate_cols, temp_col, ...).
    """
    return [Result("AxisCubic", d) for d in _core.export_cubics(models, **options)]


def export_params(models, format, calibration=None, validation=None, static_weight="auto", log=None, **options):
    """Parameter file text for an autopilot from three axis drift models (x, y, z).

    As `gyrocomp export --format px4|ardupilot` (the values; the header comments are ``comments``):
    the cubics of export_cubics (calibration, validation, static_weight; ``log``: read_log's
    keywords for the runs), written by the library (deg/s converted to rad/s there). options:
    device_id, index (px4); imu (ardupilot); comments.
    """
    if len(models) != 3:
        raise ValueError(f"export_params: three axis models are needed, got {len(models)}")
    if format not in ("px4", "ardupilot"):
        raise ValueError(f"export_params: format={format}: must be px4 or ardupilot")
    axes = export_cubics(models, calibration=calibration, validation=validation, static_weight=static_weight,
                         **(log or {}))
    cubics = [a.cubic_dps for a in axes]
    if format == "px4":
        return px4_thermal_params(cubics, **options)
    return ardupilot_thermal_params(cubics, **options)


__all__ = [
    "CancellationToken", "Cancelled", "DriftModel", "Result", "ardupilot_thermal_params", "compare_methods",
    "compute_allan", "compute_deviation", "decompose", "drift_model_from_json", "export_cubics", "export_params", "fit_drift_model",
    "flp_denoise", "generate_c", "imu_noise_files", "inspect", "kalibr_imu_yaml", "load_drift_model",
    "measure_bandwidth", "plan", "project_onto_cubic", "px4_thermal_params", "read_log", "read_log_rows",
    "run_parallel_model", "sample_entropy", "simulate", "simulate_board", "validate_drift_model", "vmd", "wavelet_denoise",
    "wflp_denoise",
]
