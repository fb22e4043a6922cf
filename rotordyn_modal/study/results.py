"""The results of a study: one labelled data set over (variant, speed, mode, ...).

:class:`StudyResult` wraps an ``xarray.Dataset`` (arrays and labels only, so it
pickles) and saves it as netCDF (classic 64-bit-offset format through scipy,
no extra engine), which opens without this package (``xarray.open_dataset``,
``netCDF4``, ``ncdump``, MATLAB, R).
"""

from __future__ import annotations

import json
import os
import weakref
from dataclasses import dataclass

import numpy as np

from ..io.text import shown_text

__all__ = ["StudyResult", "Assembly", "ResultsWriter", "FileRecords", "sweep_variables", "held_bytes", "build_dataset", "load_study", "percentile_interval", "variant_bytes"]

#: dimensions too long to spread into columns of the per-variant table
_SWEEP_DIMS = ("speed", "stability_speed")


def variant_bytes(shapes, n_parameters: int) -> int:
    """Bytes of one variant's results in memory: its outputs (float64), its parameter
    values, its failure flag and an empty error text.

    Parameters
    ----------
    shapes : dict
        Output variable -> shape per variant.
    n_parameters : int
    """
    return 8 * (sum(int(np.prod(shape)) for shape in shapes.values()) + n_parameters) + 1 + 4


def held_bytes(variables, shapes, n_parameters: int) -> int:
    """Bytes per variant that stay in memory when the results go to their file chunk by chunk
    (:class:`ResultsWriter`): what is read whole afterwards, the per-variant numbers (outputs
    without a speed dimension and the parameter values, read for the summary and the table,
    about three copies at a time) and one mode's frequencies at every speed (the Campbell
    figure's band, three copies), and the failure flags.

    Parameters
    ----------
    variables : dict
        Output variable -> dims after ``variant``.
    shapes : dict
        Output variable -> shape per variant.
    n_parameters : int
    """
    numbers = sum(int(np.prod(shapes[name])) for name in set(variables) - set(sweep_variables(variables)))
    speeds = shapes["frequency_hz"][0] if "frequency_hz" in shapes else 0
    return 3 * 8 * (numbers + n_parameters) + 3 * 8 * speeds + 2


class Assembly:
    """The study's results, assembled chunk by chunk into arrays of their final size
    (allocated when the first chunk arrives), so that memory holds the results once,
    never a list of chunks and their concatenation besides.

    Parameters
    ----------
    n_variants : int
    shapes : dict
        Output variable -> shape per variant.
    """

    def __init__(self, n_variants: int, shapes: dict):
        self.n = n_variants
        self.shapes = shapes
        self.arrays = None
        self.errors = [""] * n_variants
        self.filled = 0

    def add(self, chunk: dict) -> None:
        """Copy one chunk (``start``, ``error`` and the variables) into its rows."""
        if self.arrays is None:
            self.arrays = {name: np.empty((self.n,) + tuple(shape)) for name, shape in self.shapes.items()}
        start, errors = int(chunk["start"]), chunk["error"]
        rows = slice(start, start + len(errors))
        for name, array in self.arrays.items():
            array[rows] = chunk[name]
        for i, text in enumerate(errors.tolist()):
            if text:
                self.errors[start + i] = text
        self.filled += len(errors)

    def error_array(self) -> np.ndarray:
        """(n_variants,) str: each variant's failure ('' where it worked)."""
        return np.array(self.errors, dtype=str)


def build_dataset(chunks, values, definition, variables, coords, model, attrs=None):
    """Stack chunk results into one ``xarray.Dataset``.

    Parameters
    ----------
    chunks : Assembly or list of dict
        The results assembled (their arrays become the data set's, not copied), or the
        chunks from :func:`rotordyn_modal.study.execution.execute` in variant order.
    values : ndarray, shape (n_variants, n_parameters)
    definition : StudyDefinition
    variables : dict
        Output variable -> dims after ``variant``.
    coords : dict
        Coordinate name -> (dim, values, attrs).
    model : Model
        The base model (its description is stored as an attribute).
    attrs : dict, optional
        More global attributes.
    """
    import xarray as xr

    from .._version import __version__

    if isinstance(chunks, Assembly):
        assert chunks.filled == len(values), "every variant's chunk is assembled"
        data = {name: (("variant",) + dims, chunks.arrays[name]) for name, dims in variables.items()}
        errors = chunks.error_array()
    else:
        data = {name: (("variant",) + dims, np.concatenate([c[name] for c in chunks]))
                for name, dims in variables.items()}
        errors = np.concatenate([c["error"] for c in chunks]).astype(str)
    params = definition.parameters
    data["sample_value"] = (("variant", "parameter"), values)
    data["error"] = (("variant",), errors)
    data["failed"] = (("variant",), (errors != "").astype(np.int8))
    coordinates = {name: (dim, vals, a) for name, (dim, vals, a) in coords.items()}
    coordinates["variant"] = ("variant", np.arange(len(values)), {})
    coordinates["parameter"] = ("parameter", np.array([p.name for p in params], dtype=str), {})
    coordinates["parameter_keys"] = ("parameter", np.array([",".join(p.keys) for p in params], dtype=str), {})
    coordinates["parameter_apply"] = ("parameter", np.array([p.apply for p in params], dtype=str), {})
    coordinates["parameter_is_grid"] = ("parameter", np.array([p.is_grid for p in params], dtype=np.int8), {})
    ds = xr.Dataset(data, coords=coordinates)
    ds.attrs.update({
        "title": f"rotordyn_modal parameter study of {model.name or shown_text(model.source)}",
        "design": definition.design, "samples": definition.samples,
        "seed": -1 if definition.seed is None else definition.seed,
        "study": json.dumps(definition.raw, default=str), "model": json.dumps(model.to_dict(), default=str),
        "model_source": shown_text(model.source), "study_source": shown_text(definition.source),
        "rotordyn_modal_version": __version__,
        "conventions": "speeds in rad/s (speed_rpm coordinate in rpm); frequencies in Hz; "
                       "NaN where a quantity does not exist or the variant failed (see error)",
    })
    if definition.operating_band_rpm is not None:
        ds.attrs["operating_band_rpm"] = np.array(definition.operating_band_rpm)
    ds.attrs.update(attrs or {})
    for name, unit in _UNITS.items():
        if name in ds:
            ds[name].attrs["units"] = unit
    for name in ("unbalance_peak_amplitude", "force_peak_amplitude"):
        if name in ds:       # unbalance --amplitude's default: x(t) = amplitude cos(...) (docs/standards.md)
            ds[name].attrs["amplitude"] = "0-peak"
    for name, search in SWEPT_COLUMNS.items():
        if name in ds:       # not the exact search of unbalance and report (docs/study-file.md)
            ds[name].attrs["peak_search"] = search
    return ds


#: the netCDF attribute ``peak_search`` of a study's ``amplification_factor`` and ``required_margin_pct``
SWEPT_PEAK_SEARCH = "swept speeds (half-power points interpolated between them)"
#: ... of the peak's own columns: its speed and amplitude, and the margin of that speed
SWEPT_PEAK = "swept speeds (the largest swept peak, or the curve's largest swept value where it has none)"
#: every column of a study's ``unbalance`` analysis read off its swept speeds -> its ``peak_search``
#: attribute (:data:`..study.analyses._UNBALANCE_VARIABLES`, :data:`..study.analyses._FORCE_VARIABLES`)
SWEPT_COLUMNS = {"unbalance_peak_amplitude": SWEPT_PEAK, "unbalance_peak_speed": SWEPT_PEAK,
                 "amplification_factor": SWEPT_PEAK_SEARCH, "separation_margin_pct": SWEPT_PEAK,
                 "required_margin_pct": SWEPT_PEAK_SEARCH, "force_peak_amplitude": SWEPT_PEAK,
                 "force_peak_speed": SWEPT_PEAK}


_UNITS = {"frequency_hz": "Hz", "damping_ratio": "1", "real_part": "1/s", "whirl_ratio": "1",
          "critical_speed": "rad/s", "critical_frequency_hz": "Hz", "modal_frequency_hz": "Hz",
          "modal_damping_ratio": "1", "threshold_speed": "rad/s", "instability_speed": "rad/s", "max_real_part": "1/s",
          "unbalance_peak_speed": "rad/s", "force_peak_speed": "rad/s", "separation_margin_pct": "%",
          "required_margin_pct": "%"}


def percentile_interval(x, q: float, confidence: float = 0.95):
    """Distribution-free confidence interval of the q-th percentile from order statistics.

    The interval ``[x_(j), x_(k)]`` with ``j, k`` the binomial(n, q/100)
    quantiles of ``(1 -+ confidence) / 2`` covers the true percentile with
    probability >= ``confidence``.

    Parameters
    ----------
    x : array_like, shape (n,), finite
    q : float
        Percentile in [0, 100].
    confidence : float

    Returns
    -------
    low, high : float
    """
    from scipy.stats import binom

    x = np.sort(np.asarray(x, dtype=float))
    n = len(x)
    alpha = (1 - confidence) / 2
    j = int(binom.ppf(alpha, n, q / 100))
    k = int(binom.ppf(1 - alpha, n, q / 100)) + 1
    return float(x[max(j - 1, 0)]), float(x[min(k - 1, n - 1)])


@dataclass(frozen=True)
class StudyResult:
    """Results of a parameter study.

    Attributes
    ----------
    dataset : xarray.Dataset
        Dims ``variant`` (every variant), ``parameter``, and those of the
        analyses: ``speed`` and ``mode`` (Campbell: ``frequency_hz``,
        ``damping_ratio``, ``real_part``, ``whirl_ratio``, each
        (variant, speed, mode)), ``crossing`` (``critical_speed`` [rad/s],
        ``critical_frequency_hz``: the crossing nearest zero speed of each
        source, order and tracked mode), ``stability_speed``
        (``max_real_part``; ``threshold_speed`` [rad/s] per variant), ``mode``
        (``modal_frequency_hz``), ``output`` x ``unbalance_source`` (unbalance
        peaks and separation margins). ``sample_value`` (variant, parameter)
        holds the value set (or the factor applied); ``error`` the reason a
        variant failed ('' if it did not).
    resumed_chunks : int
        Chunks read from a checkpoint instead of computed.
    """

    dataset: object
    resumed_chunks: int = 0

    # -- the file behind it ----------------------------------------------------------------
    def close(self) -> None:
        """Let go of the results file the data set reads its curves over speed from (a study
        written with ``out=``, or one of ``rdm.study`` without it too large for memory, whose
        temporary file's space is then freed); nothing for results held in memory. The data set's
        curves cannot be read afterwards. Garbage collection does the same."""
        self.dataset.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    # -- basic views ----------------------------------------------------------------------
    @property
    def n_variants(self) -> int:
        return int(self.dataset.sizes["variant"])

    @property
    def failed(self) -> np.ndarray:
        """(n_variants,) bool: the variant failed (its outputs are NaN)."""
        return self.dataset["failed"].values.astype(bool)

    @property
    def parameters(self) -> list:
        return [str(p) for p in self.dataset["parameter"].values]

    @property
    def samples(self):
        """``pandas.DataFrame`` of the parameter values, one row per variant."""
        import pandas as pd

        return pd.DataFrame(self.dataset["sample_value"].values, columns=self.parameters,
                            index=pd.Index(self.dataset["variant"].values, name="variant"))

    def outputs(self) -> list:
        """Names of the output variables (not the samples or the errors)."""
        return [str(v) for v in self.dataset.data_vars if v not in ("sample_value", "error", "failed")]

    def to_dataframe(self, variable: str | None = None):
        """Results as a table (``pandas.DataFrame``).

        Parameters
        ----------
        variable : str, optional
            Without it: one row per variant with the parameter values, ``error``
            and every output that has no speed dimension (outputs over
            ``crossing``, ``mode``, ``output`` spread over columns such as
            ``critical_speed[motor,1,2]``). With it: the long table of that
            variable over all its dimensions, joined with the parameter values.
        """
        if variable is not None:
            table = self.dataset[variable].to_dataframe().reset_index()
            keep = [c for c in table.columns if c not in self.dataset.coords or c in self.dataset[variable].dims
                    or c in ("speed_rpm",)]
            return table[keep].join(self.samples, on="variant")
        import pandas as pd

        samples = self.samples
        columns = {"error": self.dataset["error"].values, **self.scalar_outputs()}
        return pd.concat([samples, pd.DataFrame(columns, index=samples.index)], axis=1)

    def scalar_outputs(self) -> dict:
        """Every per-variant number: column name -> ndarray (n_variants,)."""
        return {column: values for name in self.outputs() for column, values in _columns(self.dataset, name)}

    # -- statistics -------------------------------------------------------------------------
    def summary(self, variables=None, percentiles=(5.0, 50.0, 95.0), confidence: float = 0.95):
        """Mean, standard deviation and percentiles of each output, with sampling errors.

        Failed variants and NaN (a quantity that does not exist for a variant)
        are left out; ``n`` counts what is left. ``mean_se = std / sqrt(n)``;
        each percentile ``pQ`` has a distribution-free ``confidence`` interval
        ``pQ_low``, ``pQ_high`` (:func:`percentile_interval`).

        Parameters
        ----------
        variables : list of str, optional
            Column names of :meth:`scalar_outputs` (default: all).
        percentiles : sequence of float
        confidence : float

        Returns
        -------
        pandas.DataFrame, one row per output
        """
        import pandas as pd

        columns = self.scalar_outputs()
        rows = []
        for name in variables or columns:
            x = columns[name] if name in columns else self.dataset[name].values
            x = np.asarray(x, dtype=float)
            x = x[np.isfinite(x)]
            row = {"output": name, "n": len(x)}
            if len(x):
                row.update(mean=x.mean(), std=x.std(ddof=1) if len(x) > 1 else np.nan)
                row["mean_se"] = row["std"] / np.sqrt(len(x))
                for q in percentiles:
                    row[f"p{q:g}"] = np.percentile(x, q)
                    row[f"p{q:g}_low"], row[f"p{q:g}_high"] = percentile_interval(x, q, confidence)
            rows.append(row)
        return pd.DataFrame(rows)

    def frequency_bands(self, percentiles=(5.0, 95.0)):
        """Each tracked mode's damped natural frequency over the variants that succeeded, at every
        speed of the ``campbell`` analysis: its lower percentile, median and upper percentile
        (a variant where the root is no mode there, frequency 0, left out).

        Parameters
        ----------
        percentiles : (float, float)
            The lower and upper percentile [percent].

        Returns
        -------
        low, median, high : ndarray, shape (n_modes, N) [Hz]
            NaN where no variant has the mode at that speed (all NaN for a mode no variant has).
        """
        return self.frequency_envelope(percentiles)[:3]

    def frequency_envelope(self, percentiles=(5.0, 95.0)):
        """:meth:`frequency_bands` and each mode's highest frequency, from one pass over the modes
        (:meth:`mode_frequencies`: a study written to its file reads each mode once).

        Returns
        -------
        low, median, high : ndarray, shape (n_modes, N) [Hz]
            As :meth:`frequency_bands`.
        highest : ndarray, shape (n_modes,) [Hz]
            Each mode's highest frequency over the variants and speeds (NaN for a mode no
            variant has).
        """
        bands = np.full((3, self.dataset.sizes["mode"], self.dataset.sizes["speed"]), np.nan)
        highest = np.full(self.dataset.sizes["mode"], np.nan)
        for m, column in enumerate(self.mode_frequencies()):
            if np.isfinite(column).any():
                bands[:, m] = np.nanpercentile(column, [percentiles[0], 50.0, percentiles[1]], axis=0)
                highest[m] = np.nanmax(column)
        return bands[0], bands[1], bands[2], highest

    def mode_frequencies(self):
        """Each tracked mode's damped natural frequency at every speed of the ``campbell`` analysis
        over the variants that succeeded, one mode at a time (memory holds one mode's, read from
        the results file where the data set reads one).

        Yields
        ------
        ndarray, shape (n_succeeded, N) [Hz]
            NaN where the root is no mode (frequency 0) or does not exist.
        """
        ok = ~self.failed
        frequency = self.dataset["frequency_hz"]                      # (variant, speed, mode)
        for m in range(self.dataset.sizes["mode"]):
            column = frequency[:, :, m].values[ok]
            yield np.where(column > 0, column, np.nan)

    def probability_in_band(self, low: float, high: float, sources=None, orders=None, modes=None) -> dict:
        """Probability that a critical speed falls inside an operating band.

        A variant counts when any of its critical speeds (the crossings chosen by
        ``sources``, ``orders``, ``modes``; default all) has ``low <= |speed| <= high``.
        Failed variants are left out.

        Parameters
        ----------
        low, high : float
            Band [rad/s].
        sources, orders, modes : sequence, optional
            Restrict the crossings (e.g. ``sources=["motor"]``, ``orders=[1]``).

        Returns
        -------
        dict
            ``probability``, ``standard_error`` (``sqrt(p (1 - p) / n)``), ``n``,
            ``hits``, and the 95 % Wilson interval ``low``, ``high``.
        """
        ds = self.dataset
        if "critical_speed" not in ds:
            from ..errors import InputError

            raise InputError("probability_in_band needs the critical_speeds analysis in the study")
        chosen = np.ones(ds.sizes["crossing"], bool)
        for values, coord in ((sources, "crossing_source"), (orders, "crossing_order"), (modes, "crossing_mode")):
            if values is not None:
                chosen &= np.isin(ds[coord].values, list(values))
        speeds = np.abs(ds["critical_speed"].values[:, chosen])
        inside = np.any((speeds >= low) & (speeds <= high), axis=1)[~self.failed]
        n, hits = len(inside), int(inside.sum())
        if n == 0:
            return {"probability": np.nan, "standard_error": np.nan, "n": 0, "hits": 0, "low": np.nan, "high": np.nan}
        p = hits / n
        z = 1.959963984540054
        centre = (p + z * z / (2 * n)) / (1 + z * z / n)
        half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
        return {"probability": p, "standard_error": float(np.sqrt(p * (1 - p) / n)), "n": n, "hits": hits,
                "low": float(centre - half), "high": float(centre + half)}

    def sensitivity(self, variables=None):
        """Global sensitivity of each output to each parameter.

        A study with ``design = "saltelli"`` gives Sobol indices (first order
        ``S1`` and total ``ST`` with bootstrap standard errors); any other
        design gives standardised regression coefficients ``SRC`` with the
        fit's ``R2`` (``SRC^2`` is a variance share only where ``R2`` is near 1).

        Parameters
        ----------
        variables : list of str, optional
            Column names of :meth:`scalar_outputs` (default: those that vary).

        Returns
        -------
        pandas.DataFrame, one row per (output, parameter)
        """
        import pandas as pd

        from .sensitivity import sobol_indices, standardized_regression

        columns = self.scalar_outputs()
        names = variables or [c for c, v in columns.items() if _varies(v)]
        X = self.dataset["sample_value"].values
        rows = []
        for name in names:
            y = np.where(self.failed, np.nan, columns[name])
            if self.dataset.attrs.get("design") == "saltelli":
                random = self.dataset["parameter_is_grid"].values == 0
                result = sobol_indices(y, int(random.sum()))
                for i, p in enumerate(np.array(self.parameters)[random]):
                    rows.append({"output": name, "parameter": p, "S1": result["S1"][i], "S1_se": result["S1_se"][i],
                                 "ST": result["ST"][i], "ST_se": result["ST_se"][i]})
            else:
                result = standardized_regression(X, y)
                for i, p in enumerate(self.parameters):
                    rows.append({"output": name, "parameter": p, "SRC": result["SRC"][i], "R2": result["R2"]})
        return pd.DataFrame(rows)

    # -- files and figures -----------------------------------------------------------------
    def save(self, path, progress: bool = False) -> None:
        """Write the data set as netCDF (classic 64-bit offset, ``variant`` the record
        dimension), atomically, a block of variants at a time (:func:`write_netcdf`; with a
        progress bar over the variants where ``progress``)."""
        from ..io import atomic_write

        with atomic_write(path, None) as temporary:
            write_netcdf(self.dataset, temporary, progress)

    def plot_campbell(self, **kwargs):
        """Campbell diagram with tolerance bands; see :func:`rotordyn_modal.plotting.plot_study_campbell`."""
        from ..plotting.study import plot_study_campbell

        return plot_study_campbell(self, **kwargs)

    def plot_critical_histograms(self, **kwargs):
        """Histograms of critical speeds; see :func:`rotordyn_modal.plotting.plot_critical_histograms`."""
        from ..plotting.study import plot_critical_histograms

        return plot_critical_histograms(self, **kwargs)

    def plot_stability_map(self, **kwargs):
        """Threshold speed over a two-parameter grid; see :func:`rotordyn_modal.plotting.plot_study_stability_map`."""
        from ..plotting.study import plot_study_stability_map

        return plot_study_stability_map(self, **kwargs)

    def plot_sensitivity(self, variables=None, **kwargs):
        """Bar chart of :meth:`sensitivity`; see :func:`rotordyn_modal.plotting.plot_sensitivity`."""
        from ..plotting.study import plot_sensitivity

        return plot_sensitivity(self.sensitivity(variables), **kwargs)


def _varies(values) -> bool:
    finite = np.asarray(values, dtype=float)
    finite = finite[np.isfinite(finite)]
    return len(finite) > 2 and finite.std() > 0


def _columns(ds, name):
    """(column name, values over variants) of one variable, small dims spread out."""
    array = ds[name]
    dims = array.dims[1:]
    if any(d in _SWEEP_DIMS for d in dims):
        return []
    if not dims:
        return [(name, array.values)]
    labels = [_labels(ds, d) for d in dims]
    flat = array.values.reshape(array.shape[0], -1)
    names = [f"{name}[{','.join(parts)}]" for parts in np.array(np.meshgrid(*labels, indexing="ij"),
                                                                 dtype=object).reshape(len(dims), -1).T]
    return list(zip(names, flat.T))


def _labels(ds, dim):
    if dim == "crossing":
        return [f"{s},{o:g},{m}" for s, o, m in zip(ds["crossing_source"].values, ds["crossing_order"].values,
                                                     ds["crossing_mode"].values)]
    return [str(v) for v in ds[dim].values]


#: variants written per block by :func:`write_netcdf` [bytes of records]
_BLOCK_BYTES = 8 * 2**20


def write_netcdf(dataset, path, progress: bool = False) -> None:
    """Write a study's data set as netCDF 3 (64-bit offset) with ``variant`` the record
    (unlimited) dimension, a block of variants at a time, so that writing takes no more
    memory than a block (xarray's scipy writer holds a big-endian copy of every variable
    and one more of each while writing: three times the results).

    xarray writes the header and the first variant (every encoding its own: attributes,
    the ``error`` texts as characters); the records are then appended here, each laid out as
    that first one, which is checked to come out byte for byte as xarray wrote it (else
    xarray writes the whole file).

    Parameters
    ----------
    dataset : xarray.Dataset
        Dims ``variant`` first where present.
    path : str
    progress : bool
        A bar over the variants written where they take more than one block ("writing results";
        1.17 GB took about 20 s).
    """
    n = dataset.sizes["variant"]
    template = _template(dataset)
    template.to_netcdf(path, engine="scipy", format="NETCDF3_64BIT", unlimited_dims=["variant"])
    layout = _record_layout(path)
    with open(path, "r+b") as handle:
        handle.seek(-layout["size"], 2)
        start = handle.tell()
        written = handle.read()
        if _records(template, layout, written, 0, 1).tobytes() != written:  # pragma: no cover - a new encoding
            handle.close()
            dataset.to_netcdf(path, engine="scipy", format="NETCDF3_64BIT", unlimited_dims=["variant"])
            return
        handle.seek(start)
        handle.truncate()
        step = max(1, _BLOCK_BYTES // layout["size"])
        bar = _writing_bar(progress and n > step, n)       # more than one block: long enough to show
        try:
            for first in range(0, n, step):
                handle.write(_records(dataset, layout, written, first, min(n, first + step)).tobytes())
                if bar is not None:
                    bar.update(min(n, first + step) - first)
        finally:
            if bar is not None:
                bar.close()
        handle.seek(4)
        handle.write(np.array(n, ">i4").tobytes())  # numrecs


def sweep_variables(variables) -> list:
    """The output variables with a speed dimension (the large ones: Campbell curves, stability
    roots), read from the results file as they are used rather than held in memory."""
    return [name for name, dims in variables.items() if any(d in _SWEEP_DIMS for d in dims)]


def file_records(*args, **kwargs):
    """A :class:`FileRecords` that is an xarray backend array (xarray imported here, when a study
    writes its file: the package imports without it)."""
    from xarray.backends import BackendArray

    global _FileRecordsArray
    if _FileRecordsArray is None:
        _FileRecordsArray = type("_FileRecordsArray", (FileRecords, BackendArray), {"__module__": __name__})
    return _FileRecordsArray(*args, **kwargs)


_FileRecordsArray = None


class FileRecords:
    """One record variable of a study's results file, read as it is used (an xarray backend
    array): a block of records at a time through one file descriptor (``os.pread``), never
    mapped, so that memory and address space hold what is asked for, not the file.

    Parameters
    ----------
    begin : int
        Byte offset of the first record.
    layout : dict
        :func:`_record_layout` of the file.
    name : str
        The variable.
    n : int
        Records (variants).
    path : str, optional
        The file (a temporary one may be renamed: the descriptor opened here follows it).
    reopen : str, optional
        The file's final name (messages; opened again by a pickled copy). None: a temporary file
        that has no name (``rdm.study`` without ``out=``): a pickled copy carries the values.
    fd : int, optional
        A descriptor of the file, instead of ``path`` (duplicated: the caller keeps its own).
    """

    def __init__(self, begin: int, layout: dict, name: str, n: int, path=None, reopen=None, fd=None):
        _, self.offset, disk, shape, self.count = next(f for f in layout["fields"] if f[0] == name)
        self.disk, self.dtype = disk, disk.newbyteorder("=")
        self.shape = (n,) + tuple(shape)
        self.record, self.begin = layout["size"], begin
        self.reopen = None if reopen is None else str(reopen)
        self._values = None
        self._fd = os.dup(fd) if fd is not None else os.open(path, os.O_RDONLY)
        self._closer = weakref.finalize(self, os.close, self._fd)

    def close(self) -> None:
        """Close the file's descriptor (at once, rather than when garbage-collected); reading
        afterwards fails."""
        self._closer()

    def __getstate__(self):
        """A pickle (a worker's copy) opens the file by its final name; a temporary file's, which
        has none (``rdm.study`` without ``out=``), carries the values themselves."""
        state = dict(self.__dict__)
        state.pop("_fd"), state.pop("_closer")
        if self.reopen is None and self._values is None:
            state["_values"] = self._block(0, self.shape[0])
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        if self._values is None:
            self._fd = os.open(self.reopen, os.O_RDONLY)
            self._closer = weakref.finalize(self, os.close, self._fd)
        else:
            self._fd, self._closer = None, (lambda: None)

    @property
    def ndim(self) -> int:
        return len(self.shape)

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def __len__(self) -> int:
        return self.shape[0]

    def get_duck_array(self, dtype=None):
        """Every value (xarray's backend arrays' method)."""
        from xarray.core import indexing

        return self[indexing.BasicIndexer((slice(None),) * self.ndim)]

    def __getitem__(self, key):
        from xarray.core import indexing

        return indexing.explicit_indexing_adapter(key, self.shape, indexing.IndexingSupport.BASIC, self._read)

    def _read(self, key: tuple) -> np.ndarray:
        """The values of a basic key (ints and slices), read a block of records at a time (each
        block's part taken at once: memory holds the answer and one block)."""
        first, rest = key[0], (slice(None),) + tuple(key[1:])
        rows = np.arange(self.shape[0])[first if isinstance(first, slice) else slice(first, first + 1)]
        tail = np.empty((0,) + self.shape[1:], self.dtype)[rest].shape[1:]
        out = np.empty((len(rows),) + tail, self.dtype)
        step = max(1, _BLOCK_BYTES // self.record)
        if len(rows):
            for start in range(int(rows.min()), int(rows.max()) + 1, step):
                stop = min(int(rows.max()) + 1, start + step)
                chosen = np.flatnonzero((rows >= start) & (rows < stop))
                if len(chosen):
                    out[chosen] = self._block(start, stop)[rows[chosen] - start][rest]
        return out if isinstance(first, slice) else out[0]

    def _block(self, start: int, stop: int) -> np.ndarray:
        """Records start..stop-1 of the variable, shape (stop - start, ...)."""
        if self._values is not None:
            return self._values[start:stop]
        size = (stop - start) * self.record
        data = os.pread(self._fd, size, self.begin + start * self.record)
        if len(data) != size:
            raise OSError(f"{self.reopen or 'the temporary results file'}: the results file ends before its "
                          "records do")
        fields = np.frombuffer(data, np.uint8).reshape(stop - start, self.record)[:, self.offset:self.offset + self.count]
        return np.ascontiguousarray(fields).view(self.disk).reshape((stop - start,) + self.shape[1:]).astype(self.dtype)


class NewEncoding(Exception):
    """xarray lays a record out otherwise than :func:`_record_block` does (a version with a new
    encoding): the results are then assembled in memory and written by xarray."""


class ResultsWriter:
    """A study's results written to their netCDF file chunk by chunk as the chunks come, in any
    order, each into its own records: memory holds one chunk, never the results. The file is
    byte for byte the one :func:`write_netcdf` writes of the whole data set.

    The header (the text width of ``error`` included) is written for variants that do not fail;
    the failures' texts are kept (variant -> text) and, when some are wider, :meth:`finish`
    widens the records in place, from the last block to the first (one more pass over the file,
    only then).

    Parameters
    ----------
    path : str
        The file (a temporary one, renamed by the caller once finished).
    template : xarray.Dataset
        One variant's data set (:func:`build_dataset` of one chunk of one variant): its header is
        the file's.
    values : ndarray, shape (n_variants, n_parameters)
        Every variant's parameter values (``sample_value``).
    progress : bool
        A bar while the records are widened (more than one block).

    Raises
    ------
    NewEncoding
        Before anything is written to ``path``, when xarray's record is not laid out as here.
    """

    def __init__(self, path, template, values, progress: bool = False):
        self.path, self.template, self.values, self.progress = str(path), template, values, progress
        self.n = len(values)
        self.failures = {}
        self.filled = 0
        self.prefix, self.first, self.layout = _header(template)
        self.handle = open(self.path, "w+b")
        self.handle.write(self.prefix)

    def add(self, chunk: dict) -> None:
        """Write one chunk (``start``, ``error`` and the variables) into its records."""
        start, errors = int(chunk["start"]), chunk["error"]
        rows = len(errors)
        failed = errors != ""
        self.failures.update({start + i: str(errors[i]) for i in np.flatnonzero(failed)})
        plain = np.zeros(rows, dtype="U1")     # the texts go in once the file's width is known

        def column(name):
            if name == "sample_value":
                return self.values[start:start + rows]
            if name == "variant":
                return np.arange(start, start + rows)
            if name == "error":
                return plain
            if name == "failed":
                return failed.astype(np.int8)
            return chunk[name]

        block = _record_block(column, self.layout, self.first, rows)
        self.handle.seek(len(self.prefix) + start * self.layout["size"])
        self.handle.write(block.tobytes())
        self.filled += rows

    def finish(self) -> None:
        """The failures' texts and the number of records written; the file closed."""
        assert self.filled == self.n, "every variant's chunk is written"
        try:
            if self.failures:
                self._widen()
            self.handle.seek(4)
            self.handle.write(np.array(self.n, ">i4").tobytes())  # numrecs
            self.handle.flush()
        finally:
            self.close()

    def close(self) -> None:
        self.handle.close()

    def _widen(self) -> None:
        """Rewrite the records with the failures' texts in the width of the longest (in place,
        from the last block: a record only grows) and the header of that width."""
        longest = max(self.failures.values(), key=lambda text: len(text.encode("utf-8")))
        template = self.template.copy()
        template["error"] = template["error"].copy(data=np.array([longest], dtype=str))
        prefix, first, layout = _header(template)
        size = self.layout["size"]
        assert len(prefix) >= len(self.prefix) and layout["size"] >= size, "records only grow"
        offsets = {name: (offset, count) for name, offset, _, _, count in self.layout["fields"]}
        step = max(1, _BLOCK_BYTES // layout["size"])
        starts = list(range(0, self.n, step))
        bar = _writing_bar(self.progress and len(starts) > 1, self.n)
        try:
            for start in reversed(starts):
                rows = min(self.n, start + step) - start
                self.handle.seek(len(self.prefix) + start * size)
                records = np.frombuffer(self.handle.read(rows * size), np.uint8).reshape(rows, size)

                texts = np.array([self.failures.get(i, "") for i in range(start, start + rows)], dtype=str)
                block = _moved(records, offsets, layout, first, texts)
                self.handle.seek(len(prefix) + start * layout["size"])
                self.handle.write(block.tobytes())
                if bar is not None:
                    bar.update(rows)
        finally:
            if bar is not None:
                bar.close()
        self.handle.seek(0)
        self.handle.write(prefix)
        self.prefix, self.first, self.layout = prefix, first, layout


def _moved(records, offsets, layout, first_record: bytes, texts) -> np.ndarray:
    """Records laid out anew: each variable's bytes copied from ``records`` (at ``offsets``:
    name -> (offset, bytes) there) to its place in ``layout``, the ``error`` texts written.

    Parameters
    ----------
    records : ndarray of uint8, shape (rows, old record size)
    offsets : dict
    layout : dict
        :func:`_record_layout` of the new records.
    first_record : bytes
        A record of the new layout (its padding is copied).
    texts : ndarray of str, shape (rows,)
    """
    rows = len(records)
    block = np.empty((rows, layout["size"]), np.uint8)
    block[:] = np.frombuffer(first_record, np.uint8)
    for name, offset, _, shape, count in layout["fields"]:
        if name == "error":
            encoded = np.char.encode(texts, "utf-8").astype(f"S{shape[-1]}")
            block[:, offset:offset + count] = np.ascontiguousarray(encoded).view(np.uint8).reshape(rows, count)
        else:
            old, size = offsets[name]
            block[:, offset:offset + count] = records[:, old:old + size]
    return block


def _header(template):
    """What xarray writes of a one-variant data set: the bytes before the records (header and
    fixed variables), the record, and :func:`_record_layout`.

    Raises
    ------
    NewEncoding
        When :func:`_record_block` does not lay the record out byte for byte as xarray did.
    """
    import io

    written = bytes(template.to_netcdf(None, engine="scipy", format="NETCDF3_64BIT", unlimited_dims=["variant"]))
    layout = _record_layout(io.BytesIO(written))
    prefix, first = written[:-layout["size"]], written[-layout["size"]:]
    if _records(template, layout, first, 0, 1).tobytes() != first:  # pragma: no cover - a new encoding
        raise NewEncoding
    return prefix, first, layout


def _writing_bar(enabled: bool, total: int):
    """A bar over the ``total`` variants written (gone when done), or None."""
    if not enabled:
        return None
    from .._progress import tqdm

    return tqdm(total=total, desc="writing results", unit="variant", leave=False)


def _template(dataset):
    """The first variant, with the longest error text (so that the text's width is the file's)."""
    template = dataset.isel(variant=slice(0, 1))
    errors = dataset["error"].values
    if errors.size:
        longest = max(errors.tolist(), key=lambda text: len(text.encode("utf-8")))
        template["error"] = template["error"].copy(data=np.array([longest], dtype=errors.dtype))
    return template


def _record_layout(path) -> dict:
    """The record variables of a netCDF 3 file (a path or a file object) in the order of its
    records: name, byte offset in a record, on-disk dtype and shape per record; ``size`` of a
    record [bytes]."""
    from scipy.io import netcdf_file

    with netcdf_file(path, "r", mmap=False) as nc:
        records = [(name, var) for name, var in nc.variables.items() if var.isrec]
        fields, offset = [], 0
        for name, var in records:
            count = int(np.prod(var.shape[1:], dtype=np.int64)) * var.data.dtype.itemsize
            fields.append((name, offset, var.data.dtype, tuple(var.shape[1:]), count))
            offset += count if len(records) == 1 else -(-count // 4) * 4
    return {"fields": fields, "size": offset}


def _records(dataset, layout, first_record: bytes, start: int, stop: int) -> np.ndarray:
    """(stop - start, record size) bytes of variants start..stop-1 of ``dataset``, padding as in
    ``first_record`` (a variable read a block at a time: a data set that reads its file lazily
    loads the block only)."""
    return _record_block(lambda name: dataset[name][start:stop].values, layout, first_record, stop - start)


def _record_block(column, layout, first_record: bytes, rows: int) -> np.ndarray:
    """(rows, record size) bytes of ``rows`` consecutive variants, padding as in ``first_record``.

    Parameters
    ----------
    column : callable
        ``column(name)`` -> the values of the record variable ``name`` over the rows, shape
        (rows, ...) (text as str).
    layout : dict
        :func:`_record_layout` of the file.
    first_record : bytes
        A record as the netCDF writer laid it out (its padding bytes are copied).
    rows : int
    """
    block = np.empty((rows, layout["size"]), np.uint8)
    block[:] = np.frombuffer(first_record, np.uint8)
    for name, offset, dtype, shape, count in layout["fields"]:
        values = np.asarray(column(name))
        if dtype.kind == "S":  # text as characters: UTF-8, padded with NUL to the width
            values = np.char.encode(values.astype(str), "utf-8").astype(f"S{shape[-1]}")
        else:
            values = values.astype(dtype.newbyteorder(">"))
        block[:, offset:offset + count] = np.ascontiguousarray(values).view(np.uint8).reshape(rows, count)
    return block


def load_study(path) -> StudyResult:
    """Open a study saved by :meth:`StudyResult.save` (or the ``study`` command).

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    StudyResult
    """
    import xarray as xr

    from ..errors import InputError
    from ..io.limits import input_path

    path = input_path(path, "study results file")
    if not path.exists() or path.is_dir():
        raise InputError(f"{path}: expected a study results file (.nc), "
                         f"{'not a folder' if path.is_dir() else 'no such file'}")
    try:
        with xr.open_dataset(path, engine="scipy") as ds:
            result = StudyResult(ds.load())
    except (OSError, ValueError, TypeError) as error:   # empty, no NetCDF 3, unreadable: numpy's and scipy's words
        reason = " ".join(str(error).split())[:160]
        raise InputError(f"{path}: expected a study's results, a NetCDF file written by StudyResult.save or the "
                         f"study command ({reason})") from None
    if "variant" not in result.dataset.sizes or "failed" not in result.dataset:
        raise InputError(f"{path}: a NetCDF file but no study's results (no 'variant' dimension or 'failed' "
                         "variable): expected a file written by StudyResult.save or the study command")
    return result
