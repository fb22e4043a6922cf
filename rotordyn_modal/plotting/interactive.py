"""Interactive figures for notebooks (plotly, the ``interactive`` extra) and a tuning widget
(ipywidgets): hover a curve to read the mode, frequency, whirl, damping, and at a critical
speed its source and order. The matplotlib figures stay the package's report figures; these
draw the same result objects and compute nothing.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..units import rpm_text

__all__ = ["campbell_figure", "stability_figure", "overlay_figure", "TuningWidget"]

_WHIRL_COLOURS = {"forward": "#1f77b4", "backward": "#d62728", "none": "#737373"}
_ORDER_COLOURS = ["#333333", "#2ca02c", "#9467bd", "#8c564b", "#bcbd22", "#17becf"]


def _plotly():
    try:
        import plotly.graph_objects as go
    except ImportError:
        raise InputError("interactive figures need plotly: pip install 'rotordyn_modal[interactive]' "
                         "(the matplotlib figures, result.plot(), need nothing more)") from None
    return go


def campbell_figure(result, speed_unit: str = "rpm", title: str | None = None):
    """Campbell diagram with hover: mode, frequency, whirl, damping; critical speeds with source and order.

    The curves are those of the matplotlib figure: each passes through its critical speeds
    (``CampbellResult.mode_curves()``) and changes its whirl style at the speeds of
    ``CampbellResult.whirl_changes()``; hover data at those inserted points is NaN.

    Parameters
    ----------
    result : CampbellResult
    speed_unit : {'rpm', 'rad/s', 'hz'}
    title : str, optional

    Returns
    -------
    plotly.graph_objects.Figure
    """
    from ._style import speed_label, speed_scale
    from .campbell import segment_ends, segment_whirl

    go = _plotly()
    scale = speed_scale(speed_unit)
    x = result.speeds * scale
    fig = go.Figure()
    changes = result.whirl_changes()
    for m, (label, curve) in enumerate(zip(result.modes, result.mode_curves())):
        speeds, f, index = _with_changes(curve, changes[m][0], result.speeds)
        custom = _curve_data(result, m, speeds, index)
        segments = segment_whirl(np.asarray(result.whirl)[:, m], result.speeds, speeds, index, changes[m])
        for whirl, colour in _WHIRL_COLOURS.items():
            at = segment_ends(segments == whirl)
            if not at.any():
                continue
            fig.add_trace(go.Scatter(
                x=speeds * scale, y=np.where(at, f, np.nan), mode="lines", line={"color": colour, "width": 2},
                name=f"mode {label} ({whirl})", legendgroup=f"mode {label}", customdata=custom,
                hovertemplate=(f"mode {label}, {whirl} whirl<br>speed %{{x:.0f}} {speed_unit}<br>"
                               "%{y:.3f} Hz<br>damping ratio %{customdata[0]:.4f}<br>"
                               "log decrement %{customdata[1]:.3f}<br>whirl ratio %{customdata[2]:+.2f}"
                               "<extra></extra>")))
    top = 1.15 * np.nanmax(np.where(result.oscillatory, result.frequencies_hz, np.nan)) \
        if result.oscillatory.any() else 1.0
    _orders(go, fig, result, x, top, speed_unit)
    _critical(go, fig, result.critical, scale, speed_unit)
    fig.update_layout(title=title or "Campbell diagram", xaxis_title=speed_label(speed_unit),
                      yaxis_title="Damped natural frequency [Hz]", yaxis_range=[0, top], hovermode="closest",
                      template="plotly_white")
    return fig


def _inserted(speeds, index, sweep):
    """Which points of a curve (``CampbellResult.mode_curves``) are no speed of the sweep: its
    critical speeds, shape (K_m,) bool."""
    return speeds != sweep[index]


def _with_changes(curve, at, sweep):
    """A mode's curve (``CampbellResult.mode_curves``) with the speeds where its whirl label
    changes (``CampbellResult.whirl_changes``, ``at`` [rad/s], shape (C,)) among its points, each
    on the curve as drawn (straight between its points), so that the style changes there.

    Returns
    -------
    speeds, frequencies, index : ndarray, shape (K_m + C',)
        As ``mode_curves`` (C' of the changes are new points).
    """
    speeds, f, _ = curve
    new = np.setdiff1d(np.asarray(at, dtype=float), speeds)
    speeds = np.concatenate([speeds, new])
    f = np.concatenate([f, np.interp(new, curve[0], f)])
    order = np.argsort(speeds, kind="stable")
    speeds, f = speeds[order], f[order]
    return speeds, f, np.searchsorted(sweep, speeds, side="right") - 1


def _curve_data(result, m, speeds, index):
    """Hover data of mode ``m``'s curve points, shape (K_m, 3): damping ratio, log decrement
    and whirl ratio at the sweep's speeds, NaN at the inserted critical speeds (their circles
    carry their own)."""
    custom = np.column_stack([result.damping_ratios[index, m], result.log_decrements[index, m],
                              result.whirl_ratios[index, m]]).astype(float)
    custom[_inserted(speeds, index, result.speeds)] = np.nan
    return custom


def _orders(go, fig, result, x, top, unit):
    lines = result.order_frequencies()
    for i, name in enumerate(result.sources.names):
        for o, order in enumerate(result.orders):
            f = lines[i, o]
            fig.add_trace(go.Scatter(
                x=x, y=np.where(f <= top, f, np.nan), mode="lines", name=f"{order:g}X {name}",
                line={"color": _ORDER_COLOURS[i % len(_ORDER_COLOURS)], "width": 1, "dash": "dot"},
                hovertemplate=f"{order:g}X {name}<br>%{{x:.0f}} {unit}, %{{y:.3f}} Hz<extra></extra>"))


def _critical(go, fig, critical, scale, unit):
    if not len(critical):
        return
    custom = np.column_stack([critical.source.astype(object), critical.order.astype(float),
                              critical.mode.astype(object), critical.whirl.astype(object),
                              critical.damping_ratios.astype(float)])
    fig.add_trace(go.Scatter(
        x=critical.speeds * scale, y=critical.frequencies_hz, mode="markers", name="critical speeds",
        marker={"symbol": "circle-open", "size": 10, "color": "black", "line": {"width": 2}}, customdata=custom,
        hovertemplate=("critical speed %{x:.0f} " + unit + "<br>%{y:.3f} Hz<br>source %{customdata[0]}, "
                       "order %{customdata[1]:g}X<br>mode %{customdata[2]}, %{customdata[3]} whirl<br>"
                       "damping ratio %{customdata[4]:.4f}<extra></extra>")))


def stability_figure(result, speed_unit: str = "rpm", title: str | None = None):
    """Real parts over speed with hover: mode, frequency, damping, whirl; threshold speeds marked.

    Parameters
    ----------
    result : StabilityResult
    speed_unit : {'rpm', 'rad/s', 'hz'}
    title : str, optional

    Returns
    -------
    plotly.graph_objects.Figure
    """
    from ._style import speed_label, speed_scale

    go = _plotly()
    x = result.speeds * speed_scale(speed_unit)
    fig = go.Figure()
    for m, label in enumerate(result.modes):
        custom = np.column_stack([result.frequencies_hz[:, m], result.damping_ratios[:, m],
                                  result.log_decrements[:, m], result.whirl[:, m].astype(object)])
        fig.add_trace(go.Scatter(
            x=x, y=result.real_parts[:, m], mode="lines", name=f"mode {label}",
            line={"color": _WHIRL_COLOURS.get(str(result.whirl[-1, m]), "#737373")}, customdata=custom,
            hovertemplate=(f"mode {label}<br>speed %{{x:.0f}} {speed_unit}<br>real part %{{y:.4g}} 1/s<br>"
                           "%{customdata[0]:.3f} Hz, %{customdata[3]} whirl<br>damping ratio %{customdata[1]:.4f}"
                           "<br>log decrement %{customdata[2]:.3f}<extra></extra>")))
    fig.add_hline(y=0.0, line={"color": "black", "width": 1})
    for speed in result.thresholds * speed_scale(speed_unit):
        fig.add_vline(x=speed, line={"color": "#d62728", "dash": "dash"},
                      annotation_text=f"threshold {speed:.0f} {speed_unit}")
    fig.update_layout(title=title or "Stability over speed (real part > 0: unstable)",
                      xaxis_title=speed_label(speed_unit), yaxis_title="Real part of eigenvalue [1/s]",
                      hovermode="closest", template="plotly_white")
    return fig


def overlay_figure(models, measured, modes=None, title: str | None = None):
    """Model FRFs (lines) over measured ones (dots), magnitude and phase, with hover.

    Parameters
    ----------
    models, measured : list of FRFResult
        Paired by position (same speeds, names and frequency lines).
    modes : MeasuredModes, optional
        Identified modes drawn as vertical lines (hover: frequency, damping, method).
    title : str, optional

    Returns
    -------
    plotly.graph_objects.Figure
    """
    go = _plotly()
    from plotly.subplots import make_subplots

    fig = make_subplots(rows=2, cols=1, shared_xaxes=True, row_heights=[0.68, 0.32], vertical_spacing=0.04)
    palette = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"]
    for n, (model, meas) in enumerate(zip(models, measured)):
        rpm = meas.speed * 30 / np.pi
        for a, out in enumerate(meas.outputs):
            for b, inp in enumerate(meas.inputs):
                colour = palette[(n * len(meas.outputs) * len(meas.inputs) + a * len(meas.inputs) + b) % 6]
                name = f"{out} / {inp}, {rpm_text(rpm)} rpm"
                _bode_pair(go, fig, meas, a, b, name, colour, model)
    for k, f in enumerate([] if modes is None else modes.frequencies_hz):
        fig.add_vline(x=f, line={"color": "#999999", "dash": "dot"}, row=1, col=1,
                      annotation_text=f"{f:.2f} Hz, ζ {modes.damping_ratios[k]:.3f}", annotation_font_size=9)
    fig.update_yaxes(type="log", title_text=f"|H| [{measured[0].quantity}]", row=1, col=1)
    fig.update_yaxes(title_text="phase [deg]", tickvals=[-180, -90, 0, 90, 180], row=2, col=1)
    fig.update_xaxes(title_text="Frequency [Hz]", row=2, col=1)
    fig.update_layout(title=title or "Model (lines) over measurement (dots)", hovermode="closest",
                      template="plotly_white")
    return fig


def _bode_pair(go, fig, meas, a, b, name, colour, model):
    h = meas.H[a, b]
    coherence = np.full(h.shape, np.nan) if meas.coherence is None else meas.coherence[a, b]
    custom = np.column_stack([np.degrees(np.angle(h)), coherence])
    fig.add_trace(go.Scatter(x=meas.frequencies_hz, y=np.abs(h), mode="markers", marker={"size": 3, "color": colour},
                             name=f"measured {name}", legendgroup=name, customdata=custom,
                             hovertemplate=("measured " + name + "<br>%{x:.3f} Hz<br>|H| %{y:.4g}<br>"
                                            "phase %{customdata[0]:.1f} deg<br>coherence %{customdata[1]:.3f}"
                                            "<extra></extra>")), row=1, col=1)
    fig.add_trace(go.Scatter(x=meas.frequencies_hz, y=custom[:, 0], mode="markers",
                             marker={"size": 3, "color": colour}, showlegend=False, legendgroup=name,
                             hoverinfo="skip"), row=2, col=1)
    hm = model.H[model.outputs.index(meas.outputs[a]), model.inputs.index(meas.inputs[b])]
    fig.add_trace(go.Scatter(x=model.frequencies_hz, y=np.abs(hm), mode="lines", line={"color": colour},
                             name=f"model {name}", legendgroup=name,
                             hovertemplate="model " + name + "<br>%{x:.3f} Hz<br>|H| %{y:.4g}<extra></extra>"),
                  row=1, col=1)
    fig.add_trace(go.Scatter(x=model.frequencies_hz, y=np.degrees(np.angle(hm)), mode="lines",
                             line={"color": colour}, showlegend=False, legendgroup=name, hoverinfo="skip"),
                  row=2, col=1)


class TuningWidget:
    """Sliders on model parameters that redraw the FRF overlay against a measurement.

    Each slider is a factor on a dotted key (log scale, ``low`` to ``high``); moving one
    recomputes the model's FRFs on the measured lines and redraws the matplotlib overlay, with
    the FRAC of every FRF in the title. Without a notebook front end (a script, a test),
    :meth:`update` does the same with the factors given.

    Parameters
    ----------
    model : Model
    measured : list of FRFResult
    keys : list of str
        Dotted keys of the model (e.g. ``suspensions.mount-FL.stiffness``).
    low, high : float
        Slider range of every factor.
    pairs : list of (output, input), optional
        FRFs drawn (of the first measured set; default: its first four); the FRAC in the
        title is the mean over every FRF of every set.
    """

    def __init__(self, model, measured, keys, low: float = 0.25, high: float = 4.0, pairs=None):
        self.model, self.measured, self.keys = model, list(measured), list(keys)
        self.low, self.high = float(low), float(high)
        first = self.measured[0]
        finite = [(o, i) for a, o in enumerate(first.outputs) for b, i in enumerate(first.inputs)
                  if np.isfinite(first.H[a, b]).all()]
        self.pairs = list(pairs) if pairs is not None else finite[:4]
        self.factors = {k: 1.0 for k in self.keys}
        self.figure = None

    def model_with_factors(self, factors=None):
        """The model with the factors applied (default: the current ones)."""
        return self.model.scaled(dict(self.factors if factors is None else factors))

    def update(self, **factors):
        """Set factors (``key=value`` with dots spelled out in a dict: ``update(**{key: 1.2})``) and redraw.

        Returns
        -------
        matplotlib.figure.Figure
        """
        unknown = sorted(set(factors) - set(self.keys))
        if unknown:
            raise InputError(f"tuning: unknown key(s) {', '.join(unknown)}; the sliders are {', '.join(self.keys)}")
        self.factors.update({k: float(v) for k, v in factors.items()})
        return self._draw()

    def _draw(self):
        from ..analysis.correlation import frac
        from ..analysis.frf import frf
        from .frf import plot_frf

        import matplotlib.pyplot as plt

        tuned = self.model_with_factors()
        models = [frf(tuned, m.speed, m.frequencies_hz, inputs=list(m.inputs), outputs=list(m.outputs),
                      quantity=m.quantity) for m in self.measured]
        fracs = [frac(a.H[np.isfinite(m.H).all(axis=-1)], m.H[np.isfinite(m.H).all(axis=-1)])
                 for a, m in zip(models, self.measured)]
        if self.figure is not None:
            plt.close(self.figure)
        settings = ", ".join(f"{k.split('.', 1)[-1]} x{v:.3g}" for k, v in self.factors.items())
        self.figure = plot_frf(models[0], measured=self.measured[0], pairs=self.pairs,
                               title=f"{settings}\nmean FRAC {np.mean(np.concatenate(fracs)):.3f}")
        return self.figure

    def widget(self):
        """The ipywidgets box (sliders and the figure's output area) for a notebook."""
        try:
            import ipywidgets as widgets
        except ImportError:
            raise InputError("the tuning widget needs ipywidgets: pip install 'rotordyn_modal[interactive]'") from None
        output = widgets.Output()
        sliders = [widgets.FloatLogSlider(value=self.factors[k], base=10, min=np.log10(self.low),
                                          max=np.log10(self.high), step=0.01, description=k.split(".", 1)[-1],
                                          continuous_update=False, style={"description_width": "initial"},
                                          layout={"width": "480px"}) for k in self.keys]

        def redraw(change=None):
            with output:
                output.clear_output(wait=True)
                fig = self.update(**{k: s.value for k, s in zip(self.keys, sliders)})
                from IPython.display import display

                display(fig)

        for slider in sliders:
            slider.observe(redraw, names="value")
        redraw()
        return widgets.VBox(sliders + [output])
