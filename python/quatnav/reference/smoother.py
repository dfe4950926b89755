"""Reference (numpy) Rauch-Tung-Striebel backward pass in error-state form, the twin of
``cpp/include/quatnav/core/smoother.hpp``.

A forward run gives, for every sample ``k``, the posterior ``posts[k]`` (whatever the filter's
model understands: a nominal state and its covariance) and how sample ``k`` is linked to
``k + 1``:

* ``(prior, Phi)``: a time update, with the prior of sample ``k + 1`` and the error-state
  transition ``Phi`` of that step;
* ``"same"``: the time update was refused (the state did not move);
* ``None``: no link (a reset, a (re)initialization).

The backward pass, from the last sample to the first::

    C    = P_k Phi^T P_prior^-1
    d    = C (x^s_{k+1} [-] x_prior)          x^s_k = x_k [+] d
    P^s_k = P_k + C (P^s_{k+1} - P_prior) C^T

with the filter's own error-state chart ``local`` ([-]) and ``retract`` ([+]). The twin keeps
every posterior in memory (the C++ pass stores them compactly and recomputes the rest).
"""
from __future__ import annotations

import numpy as np


def rts_step(P, Phi, P_prior, d_next, Ps_next):
    """One backward step: ``(d, Ps)`` from the posterior covariance ``P`` at k, the transition
    ``Phi``, the prior covariance ``P_prior`` at k + 1, the smoothed correction of that prior
    ``d_next`` and the smoothed covariance ``Ps_next`` at k + 1. The gain by a Cholesky solve."""
    L = np.linalg.cholesky(P_prior)
    B = P @ Phi.T
    C = np.linalg.solve(L.T, np.linalg.solve(L, B.T)).T   # C = B P_prior^-1
    d = C @ d_next
    Ps = P + C @ (Ps_next - P_prior) @ C.T
    return d, 0.5 * (Ps + Ps.T)


def rts(posts, links, error_covariance, local, retract):
    """Smoothed states and error covariances of a forward run.

    Parameters
    ----------
    posts : list
        The posterior of every sample, in order.
    links : list
        ``links[k]`` (k < len(posts) - 1) links sample k to k + 1 (see the module docstring).
    error_covariance : callable
        ``error_covariance(post) -> P`` in the error coordinates of ``post``.
    local : callable
        ``local(base, x) -> d`` with ``x = base [+] d``.
    retract : callable
        ``retract(base, d, Ps) -> x``: the state ``base [+] d`` with the error covariance ``Ps``.

    Returns
    -------
    (list, list)
        The smoothed states (as ``retract`` makes them) and error covariances.
    """
    n = len(posts)
    xs, Ps = [None] * n, [None] * n
    xs[-1], Ps[-1] = posts[-1], error_covariance(posts[-1])
    for k in range(n - 2, -1, -1):
        link = links[k]
        if isinstance(link, str) and link == "same":
            xs[k], Ps[k] = xs[k + 1], Ps[k + 1]
            continue
        P = error_covariance(posts[k])
        if link is None:
            xs[k], Ps[k] = posts[k], P
            continue
        prior, Phi = link
        try:
            d, Ps[k] = rts_step(P, Phi, error_covariance(prior), local(prior, xs[k + 1]), Ps[k + 1])
        except np.linalg.LinAlgError:  # P_prior not positive definite: no link, as in C++
            xs[k], Ps[k] = posts[k], P
            continue
        xs[k] = retract(posts[k], d, Ps[k])
    return xs, Ps


class Recorder:
    """The forward record of a batch run, the twin of ``RtsSmoother``'s ``after_predict`` /
    ``after_sample`` (a twin's ``run(..., observer=Recorder(model))``): the posterior of every
    sample from the first at which the filter has an estimate, and the links between them.

    ``model`` provides ``snapshot(f)`` (the posterior, or None while the filter has no estimate),
    ``same(a, b)``, ``transition(post, k)`` (the error-state transition of the time update of
    sample k from the posterior ``post``), ``error_covariance``, ``local`` and ``retract`` (see
    :func:`rts`). A time update that left the state as it was is a refused one: link ``"same"``.
    """

    def __init__(self, model):
        self.model = model
        self.first = None
        self.posts, self.links = [], []
        self._pending = None

    def after_predict(self, k, f):
        prior = self.model.snapshot(f)
        if not self.posts or prior is None:
            self._pending = None
            return
        post = self.posts[-1]
        link = "same" if self.model.same(prior, post) else (prior, self.model.transition(post, k))
        self._pending = (k, link)

    def after_sample(self, k, f):
        s = self.model.snapshot(f)
        if s is None:
            return
        if self.first is None:
            self.first = k
        else:
            self.links.append(self._pending[1] if self._pending is not None and self._pending[0] == k else None)
        self.posts.append(s)
        self._pending = None

    def smooth(self):
        """``(first, states, covariances)``: the smoothed samples ``first``, ``first + 1``, ..."""
        m = self.model
        xs, Ps = rts(self.posts, self.links, m.error_covariance, m.local, m.retract)
        return self.first, xs, Ps
