"""Classifier inputs from feature tables: order-normalised by default, leaks opt-in.

:class:`OrderFeatures` turns the ``CHANNEL__FEATURE`` columns of a dataset row (or of
``rubdiag features`` on a measurement, prefixed the same way) into what a classifier
should see. Families (``families=``):

``orders`` (default)
    Each half and third order's amplitude over the channel's level (``rel_amp_<k>``), how
    far the line sits from its nominal order (``dev_<k>``, in orders; not for 1×, below),
    and the counts of fractional lines (``n_half_orders``, ``n_third_orders``).
``sidebands`` (default)
    Sideband spacing in orders (``sb_<n>x_delta_order``), the two sidebands over the
    channel's level, and the broadband RMS around n× over the channel's *noise floor*
    (``bb_<n>x_over_floor``; below).
``combinations`` (default)
    The strongest pair f_a + f_b = m×: both frequencies in orders, m, both amplitudes over
    the channel's level.
``levels`` (opt-in)
    Absolute levels: the RMS and every order's amplitude, in the channel's unit. A rubbing
    rotor's 1× levels off at about the gap, so levels encode the gap band rather than rub.
``absolute`` (opt-in)
    Absolute frequencies: ``speed_rpm`` (once), every ``freq_<k>_hz``, sideband spacings in
    Hz, the pair's frequencies in Hz. With two cases at different speeds, the speed gives
    the case (and what it implies) away.

``full_spectrum`` (opt-in)
    Of every probe pair whose two probes are among the channels (``<node>_yz_disp``,
    :func:`rubdiag.dataset._schema.pair_channel`): the forward and reverse amplitude at each
    order over the pair's level (``fwd_rel_<k>``, ``rev_rel_<k>``), the reverse share of the
    non-1× motion, the 1× ellipticity and the 1× precession direction (+1 / −1).
``orbit`` (opt-in)
    Of the same pairs: the orbit's flattening, the share of time near its clearance-limited
    radius, and that radius over the pair's level (``limit_radius_rel``) — no length.

The pair families read the columns a dataset row has for its probe pairs
(:mod:`rubdiag.dataset._rows`); a frame without them (a dataset made before they existed,
or a measurement's ``rubdiag features`` table) gives these families nothing, so a
pipeline asking for them still fits on the other families. A pair's *level* is the RMS of
its complex signal within the searched orders, √Σ(fwd² + rev²): a length like the
channels' level, so every ratio is scale-free. They are **not default**: the features of a
measurement computed by :mod:`rubdiag.learn._predict` and of the noise curves
(:mod:`rubdiag.learn._robustness`) are single-channel tables without pair columns, so a
default model using them could not be applied to a measurement or noise-tested; name them
(``families=[..., "full_spectrum", "orbit"]``) for a model meant for dataset rows. The
pair columns a fitted model reads are ``pair_required_`` (beside ``required_``, the
channels' own columns, which already reach the highest order a pair line does).

Phases are never used: an absolute phase depends on where the record starts.

The channel's *level*, which every ratio divides by, is its RMS within the orders the table
searches: the power of the half- and third-order lines (``amp_<k>² / 2``) plus the
broadband power around each harmonic (``bb_<n>x_rms²``, n× ± 0.25× without the n× line).
Not the record's ``rms``: that one holds everything up to the Nyquist frequency, so a
channel with broadband noise would change its ratios with the sampling rate (by √2 from
10 kHz to 5 kHz for white noise), and a model would read a measurement sampled otherwise
than its training data as another machine.

There is no ``dev_1x``: the 1× line *is* the speed (a tacho's, or the line itself when the
speed is estimated), so its offset from order 1 measures only how well the speed was
measured — about 1e-7 in simulation, where the speed is exact, a few 1e-6 from a tacho. A
forest on 24 runs gave it 5 % of its importance; without it, the largest change of a
class probability between a run and its record resampled to 5 kHz fell from 0.077 to 0.033
(``tests/learn/test_predict.py``).

The broadband around n× (``bb_<n>x_rms``) is divided by the channel's floor — its
quietest band, the smallest ``bb_<n>x_rms`` over the harmonics — and not by the
level. Without rub every band holds only measurement noise, so all of them are ≈ 1 however
loud the machine or its sensor noise; rub lifts the bands near the low harmonics above the
others. Over the level, the same noise reads as (noise / response): a run far from the
critical, or a sensor a little noisier than the simulation's, looked like rub. Measured
on the classifier dataset of the documentation (rf, grouped split, trained at the dataset's floor,
tested with noise added 40 dB below the rubbing runs' power): rub/no-rub macro-F1 fell
from 0.98 to 0.40 with the bands over the level, from 0.99 to 0.98 over the floor
(``noise_curve(..., train_on="stored")``; documentation: "The classifier table").
A record without noise (a simulation's raw output) has no floor: its quietest band is
round-off, and every band over it would read 1e4 and more. The floor is therefore taken no
lower than 1e-4 of the level, and a band reads no lower than the floor
(:mod:`rubdiag.signal._bandfloor`: the rule and why that value).

Missing values, explicitly: a feature table writes an absent line as amplitude 0 and
location NaN, and an unmeasurable one (above Nyquist, a record too short) as all NaN. Here
every ratio or location that is NaN becomes 0 — "not seen", the value an absent line has —
and a column that was NaN in every training row is dropped at ``fit`` (``dropped_`` lists
them), so that no column is constant by construction and no imputer ever sees an all-NaN
column. ``required_`` lists the raw columns the kept features come from: a measurement
that cannot provide one (its sampling rate is too low for the model's highest order) is
refused by :mod:`rubdiag.learn._predict`, not silently filled.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from rubdiag.dataset._schema import PAIR_FEATURES, SEPARATOR, pair_channel
from rubdiag.learn._columns import channels_of
from rubdiag.signal._bandfloor import channel_floor, over_floor
from rubdiag.signal._orders import HALF_ORDERS, HARMONICS, THIRD_ORDERS, order_label

__all__ = ["DEFAULT_FAMILIES", "FAMILIES", "PAIR_FAMILIES", "OrderFeatures", "SelectColumns",
           "pairs_of"]

FAMILIES = ("orders", "sidebands", "combinations", "levels", "absolute", "full_spectrum",
            "orbit")
DEFAULT_FAMILIES = ("orders", "sidebands", "combinations")
#: The families of probe pairs (module docstring): their channels are pairs, not sensors.
PAIR_FAMILIES = ("full_spectrum", "orbit")

_HALF = [(order_label(k), k) for k in HALF_ORDERS]
_THIRD = [order_label(k) for k in THIRD_ORDERS]


def _recipes(family: str) -> list[tuple[str, str, str]]:
    """(output name, raw feature, how) of one channel (of a family in
    :data:`PAIR_FAMILIES`: of one probe pair): ``how`` is ``ratio`` (over the level),
    ``pair_ratio`` (over the pair's level),
    ``floor`` (over the noise floor), ``order`` (Hz over 1×), ``dev:<k>`` (Hz over 1× minus
    k) or ``raw``."""
    if family == "orders":
        return ([(f"rel_amp_{k}", f"amp_{k}", "ratio") for k, _ in _HALF]
                + [(f"rel_amp_{k}", f"amp_{k}", "ratio") for k in _THIRD]
                + [(f"dev_{k}", f"freq_{k}_hz", f"dev:{v!r}") for k, v in _HALF if v != 1.0]
                + [("n_half_orders", "n_half_orders", "raw"),
                   ("n_third_orders", "n_third_orders", "raw")])
    if family == "sidebands":
        out = []
        for n in HARMONICS:
            out += [(f"sb_{n}x_delta_order", f"sb_{n}x_delta_hz", "order"),
                    (f"sb_{n}x_rel_lower", f"sb_{n}x_lower", "ratio"),
                    (f"sb_{n}x_rel_upper", f"sb_{n}x_upper", "ratio"),
                    (f"bb_{n}x_over_floor", f"bb_{n}x_rms", "floor")]
        return out
    if family == "combinations":
        return [("combo_fa_order", "combo_fa_hz", "order"),
                ("combo_fb_order", "combo_fb_hz", "order"),
                ("combo_order", "combo_order", "raw"),
                ("combo_rel_amp_a", "combo_amp_a", "ratio"),
                ("combo_rel_amp_b", "combo_amp_b", "ratio")]
    if family == "levels":
        return ([("rms", "rms", "raw")] + [(f"amp_{k}", f"amp_{k}", "raw") for k, _ in _HALF]
                + [(f"amp_{k}", f"amp_{k}", "raw") for k in _THIRD])
    if family == "absolute":
        return ([(f"freq_{k}_hz", f"freq_{k}_hz", "raw") for k, _ in _HALF]
                + [(f"sb_{n}x_delta_hz", f"sb_{n}x_delta_hz", "raw") for n in HARMONICS]
                + [("combo_fa_hz", "combo_fa_hz", "raw"), ("combo_fb_hz", "combo_fb_hz", "raw")])
    if family == "full_spectrum":
        return ([(f"{n[:3]}_rel_{n[4:]}", n, "pair_ratio") for n in _PAIR_LINES]
                + [(n, n, "raw") for n in ("reverse_share", "ellipticity_1x", "precession_1x")])
    if family == "orbit":
        return [("flattening", "flattening", "raw"),
                ("near_limit_share", "near_limit_share", "raw"),
                ("limit_radius_rel", "limit_radius", "pair_ratio")]
    raise ValueError(f"families: {family!r} is not a feature family (allowed: "
                     f"{', '.join(FAMILIES)})")


#: A pair's forward and reverse lines: its level's raw features.
_PAIR_LINES = [n for n in PAIR_FEATURES if n.startswith(("fwd_", "rev_"))]

#: The raw features of a channel's level: every order line, the broadband around n×.
_LEVEL = ([f"amp_{k}" for k, _ in _HALF] + [f"amp_{k}" for k in _THIRD]
          + [f"bb_{n}x_rms" for n in HARMONICS])


def _level(X: pd.DataFrame, channel: str) -> np.ndarray:
    """The channel's RMS within the searched orders (module docstring); a line or band
    not measured (NaN) adds nothing."""
    v = np.nan_to_num(X[[f"{channel}{SEPARATOR}{n}" for n in _LEVEL]].to_numpy(np.float64))
    power = np.where([n.startswith("amp_") for n in _LEVEL], 0.5, 1.0) * v * v
    return np.sqrt(power.sum(axis=1))


def _pair_level(X: pd.DataFrame, pair: str) -> np.ndarray:
    """The pair's RMS within the searched orders, √Σ(fwd² + rev²) (module docstring)."""
    v = np.nan_to_num(X[[f"{pair}{SEPARATOR}{n}" for n in _PAIR_LINES]].to_numpy(np.float64))
    return np.sqrt((v * v).sum(axis=1))


def pairs_of(X: pd.DataFrame, channels) -> list[str]:
    """The probe pairs of ``channels`` that ``X`` has columns for: every pair channel
    (:func:`~rubdiag.dataset._schema.pair_channel`) of two of ``channels``, each feature of
    :data:`~rubdiag.dataset._schema.PAIR_FEATURES` present, in the order of the y probes."""
    present = set(X.columns)
    out = []
    for y in channels:
        for z in channels:
            pair = pair_channel(y, z)
            if pair is not None and pair not in out and all(
                    f"{pair}{SEPARATOR}{n}" in present for n in PAIR_FEATURES):
                out.append(pair)
    return out


def _floor(X: pd.DataFrame, channel: str) -> np.ndarray:
    """The channel's noise floor: its smallest broadband RMS around a harmonic, no lower
    than a fraction of its level (:func:`rubdiag.signal._bandfloor.channel_floor`); NaN
    for a still channel (then nothing is over the floor)."""
    v = X[[f"{channel}{SEPARATOR}bb_{n}x_rms" for n in HARMONICS]].to_numpy(np.float64)
    return channel_floor(v, _level(X, channel))


def _check_families(families) -> tuple[str, ...]:
    if isinstance(families, str):
        families = (families,)
    families = tuple(families)
    for f in families:
        _recipes(f)                      # raises on an unknown name
    if not families:
        raise ValueError(f"families is empty (allowed: some of {', '.join(FAMILIES)})")
    return families


class OrderFeatures(TransformerMixin, BaseEstimator):
    """Classifier features of the channels of a feature table (module docstring).

    Input is a DataFrame with ``speed_rpm`` and the ``C__feature`` columns of the channels
    (other columns are ignored); output a float array, named by
    ``get_feature_names_out`` (``C__rel_amp_1p5x`` …).

    Parameters
    ----------
    channels : sequence of str, optional
        The channels to use (``C`` of the ``C__feature`` columns). None: every channel of
        the training frame.
    families : sequence of str
        Feature families (module docstring); default orders, sidebands, combinations.
    """

    def __init__(self, channels=None, families=DEFAULT_FAMILIES):
        self.channels = channels
        self.families = families

    def fit(self, X, y=None):
        if not isinstance(X, pd.DataFrame):
            raise TypeError("OrderFeatures needs a DataFrame with C__feature columns "
                            "(a dataset's rows or a prefixed feature table)")
        families = _check_families(self.families)
        available = channels_of(X)
        if self.channels is None:
            channels = available
        else:
            channels = [self.channels] if isinstance(self.channels, str) else list(self.channels)
            missing = [c for c in channels if c not in available]
            if missing:
                raise ValueError(f"channels: {missing[0]!r} is not a channel of the data "
                                 f"(its channels: {', '.join(available) or 'none'})")
        if not channels:
            raise ValueError("no channel to learn from (channels is empty)")
        pairs = pairs_of(X, channels)
        recipes = [(f"{c}{SEPARATOR}{name}", f"{c}{SEPARATOR}{raw}", c, how)
                   for c in channels for fam in families if fam not in PAIR_FAMILIES
                   for name, raw, how in _recipes(fam)]
        recipes += [(f"{p}{SEPARATOR}{name}", f"{p}{SEPARATOR}{raw}", p, how)
                    for p in pairs for fam in families if fam in PAIR_FAMILIES
                    for name, raw, how in _recipes(fam)]
        if not recipes:
            raise ValueError(f"families {', '.join(families)}: the data has no probe pair "
                             "of the channels (no <node>_yz_disp__ columns), so nothing to "
                             "learn from")
        if "absolute" in families:
            recipes.insert(0, ("speed_rpm", "speed_rpm", None, "raw"))
        values = self._compute(X, recipes, fill=False)
        measured = ~np.isnan(values).all(axis=0)
        self.channels_ = channels
        self.recipes_ = [r for r, keep in zip(recipes, measured, strict=True) if keep]
        self.dropped_ = [r[0] for r, keep in zip(recipes, measured, strict=True) if not keep]
        kept_pairs = {r[2] for r in self.recipes_ if r[2] in pairs}
        self.pairs_ = [p for p in pairs if p in kept_pairs]
        self.required_ = sorted({r[1] for r in self.recipes_ if r[2] not in kept_pairs}
                                | {"speed_rpm"}
                                | {f"{c}{SEPARATOR}{n}" for c in channels for n in _LEVEL})
        self.pair_required_ = sorted({r[1] for r in self.recipes_ if r[2] in kept_pairs}
                                     | {f"{p}{SEPARATOR}{n}" for p in self.pairs_
                                        for n in _PAIR_LINES})
        self.n_features_out_ = len(self.recipes_)
        return self

    def transform(self, X):
        check_is_fitted(self, "recipes_")
        needed = [*self.required_, *getattr(self, "pair_required_", ())]  # (older models)
        missing = [c for c in needed if c not in getattr(X, "columns", ())]
        if missing:
            pairs = getattr(self, "pairs_", ())
            also = f" and probe pairs {', '.join(pairs)}" if pairs else ""
            raise ValueError(f"the data has no column {missing[0]!r} (the model was trained "
                             f"on channels {', '.join(self.channels_)}{also})")
        return self._compute(X, self.recipes_, fill=True)

    def get_feature_names_out(self, input_features=None):
        check_is_fitted(self, "recipes_")
        return np.asarray([r[0] for r in self.recipes_], dtype=object)

    @staticmethod
    def _compute(X: pd.DataFrame, recipes, fill: bool) -> np.ndarray:
        f1 = X["speed_rpm"].to_numpy(dtype=np.float64) / 60.0
        out = np.empty((len(X), len(recipes)))
        levels, floors = {}, {}
        for j, (_, raw, channel, how) in enumerate(recipes):
            v = X[raw].to_numpy(dtype=np.float64)
            if how in ("ratio", "pair_ratio"):
                if channel not in levels:
                    levels[channel] = (_level if how == "ratio" else _pair_level)(X, channel)
                level = levels[channel]
                with np.errstate(divide="ignore", invalid="ignore"):
                    v = np.where(level > 0.0, v / level, 0.0 * v)   # a still channel: no line
            elif how == "floor":
                if channel not in floors:
                    floors[channel] = _floor(X, channel)
                v = over_floor(v, floors[channel])
            elif how == "order":
                v = v / f1
            elif how.startswith("dev:"):
                v = v / f1 - float(how[4:])
            out[:, j] = v
        if fill:
            np.nan_to_num(out, copy=False, nan=0.0)
        return out


class SelectColumns(TransformerMixin, BaseEstimator):
    """The given columns of a DataFrame as floats (NaN as 0): the baselines' input.

    Parameters
    ----------
    columns : sequence of str
        The columns.
    """

    def __init__(self, columns=()):
        self.columns = columns

    def fit(self, X, y=None):
        columns = list(self.columns)
        missing = [c for c in columns if c not in X.columns]
        if missing or not columns:
            raise ValueError(f"SelectColumns: column {missing[0]!r} is not in the data"
                             if missing else "SelectColumns: no column given")
        self.columns_ = columns
        return self

    def transform(self, X):
        check_is_fitted(self, "columns_")
        return np.nan_to_num(X[self.columns_].to_numpy(dtype=np.float64), nan=0.0)

    def get_feature_names_out(self, input_features=None):
        check_is_fitted(self, "columns_")
        return np.asarray(self.columns_, dtype=object)
