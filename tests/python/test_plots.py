"""Every figure the package makes is written without error and shows what it claims to (axes in
the stated scale, shading where stated). The data-based ones skip when the shared data is absent;
all skip when matplotlib is not installed."""
import numpy as np
import pytest

pytest.importorskip("matplotlib")


def _png_ok(path, min_w=600, min_h=300):
    """The file is a PNG of a real figure (size, and more than a handful of colours)."""
    import matplotlib.image as mpimg
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", path
    img = mpimg.imread(path)
    assert img.shape[1] >= min_w and img.shape[0] >= min_h, img.shape
    rgb = (img[..., :3] * 255).astype(np.uint8).reshape(-1, 3)
    assert len(np.unique(rgb, axis=0)) > 50, "the figure is almost blank"


def _legends_outside(fig):
    """Every legend of the figure lies outside the data area of its axes."""
    if not hasattr(fig.canvas, "get_renderer"):  # a Figure made without pyplot
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        FigureCanvasAgg(fig)
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    n = 0
    for ax in fig.axes:
        leg = ax.get_legend()
        if leg is None:
            continue
        n += 1
        lb, ab = leg.get_window_extent(r), ax.get_window_extent(r)
        overlap_w = min(lb.x1, ab.x1) - max(lb.x0, ab.x0)
        overlap_h = min(lb.y1, ab.y1) - max(lb.y0, ab.y0)
        assert overlap_w <= 1 or overlap_h <= 1, f"legend inside the axes {ax.get_ylabel()!r}"
    assert n > 0


def test_moving_rms_matches_direct_windows():
    from quatnav._plotting import moving_rms
    rng = np.random.default_rng(1)
    x = rng.standard_normal((50, 2))
    x[7, 1] = np.nan
    y = moving_rms(x, 5)
    for i in (0, 1, 10, 25, 49):
        w = x[max(0, i - 2):i + 3]
        want = np.sqrt(np.nanmean(w ** 2, axis=0))
        assert y[i] == pytest.approx(want)


def test_demo_figure_attitude_filters_only(tmp_path):
    """The demo's figure with the attitude filters alone (the navigation parts need scipy)."""
    import quatnav
    from quatnav import demo
    d = demo.rotation_scenario(n=1500)
    res = {"QuaternionEKF": {"result": quatnav.QuaternionEKF().run(d.gyr, d.acc, d.mag, dt=d.dt)},
           "MargFilter": {"result": quatnav.MargFilter().run(d.gyr, d.acc, d.mag, dt=d.dt)}}
    out = demo._plot(d, res, None, None, tmp_path / "sub" / "demo.png")
    assert out == tmp_path / "sub" / "demo.png"
    _png_ok(out)


def test_gpsins_figure(tmp_path):
    pytest.importorskip("quatnav.sim")
    from quatnav.experiments import gpsins as G
    res = G.run_scenario("turntable", keep_series=True)
    with pytest.raises(ValueError, match="keep_series"):
        G.plot({k: v for k, v in res.items() if k != "series"}, tmp_path / "x.png")
    fig = G.plot(res, tmp_path / "gpsins.png")
    _png_ok(tmp_path / "gpsins.png")
    _legends_outside(fig)
    # The outage is shaded in every panel, over exactly its window.
    o = res["outage"]
    for ax in fig.axes:
        (x0, x1), = [(p.get_window_extent().transformed(ax.transData.inverted()).x0,
                      p.get_window_extent().transformed(ax.transData.inverted()).x1) for p in ax.patches]
        assert x0 == pytest.approx(o["start_s"], abs=0.05) and x1 == pytest.approx(o["start_s"] + 10, abs=0.05)


def test_nav13_figure(tmp_path):
    pytest.importorskip("quatnav.sim")
    from quatnav.experiments import nav13 as X
    mc = X.monte_carlo(1, decimate=20)
    fig = X.plot(mc, tmp_path / "nav13.png", 1, "paper")
    _png_ok(tmp_path / "nav13.png")
    _legends_outside(fig)
    assert all(ax.get_yscale() == "log" for ax in fig.axes)


def test_marg_turn_figure(tmp_path):
    pytest.importorskip("quatnav.sim")
    from quatnav.experiments import marg_turn as MT
    from quatnav.sim import make_scenario
    r = MT.run_seed(make_scenario(MT.SCENARIO, seed=0), keep_series=True)
    fig = MT.plot(r["series"], tmp_path / "turn.png")
    _png_ok(tmp_path / "turn.png")
    _legends_outside(fig)


def test_navego_figure(data_dir, tmp_path):
    from quatnav.experiments import navego
    _, arrays = navego.run_navego(data_dir / "navego_synthetic", seconds=150.0)
    fig = navego.plot(arrays, tmp_path / "navego.png")
    _png_ok(tmp_path / "navego.png")
    _legends_outside(fig)
    pos_h, pos_v, vel, att = fig.axes
    assert pos_h.get_yscale() == "log" and pos_v.get_yscale() == "log"
    # The attitude axis holds the steady part, not the initial alignment's three-sigma.
    s3 = 3 * np.degrees(arrays["sigma"][:, 6:9])
    top = att.get_ylim()[1]
    assert top < 0.25 * s3.max()
    assert top > np.max(np.abs(arrays["deul"][arrays["t"] > 100.0]))


def test_walk_rtk_figure_shades_outages_only_over_data(data_dir, tmp_path):
    from quatnav.experiments import walk_rtk as W
    summary, arrays = W.run_walk(data_dir / "gnss_imu_walk")
    fig = W.plot(summary, arrays, tmp_path / "walk.png")
    _png_ok(tmp_path / "walk.png")
    _legends_outside(fig)
    t0 = summary["t0"]
    shaded_total = 0.0
    for ax, name in zip(fig.axes, ("rtk_outages", "degraded_outages")):
        assert ax.get_yscale() == "log"
        tr = arrays[name]["t"] - t0
        spans = W._spans(tr)
        for p in ax.patches:
            b = p.get_window_extent().transformed(ax.transData.inverted())
            assert any(g0 - 0.05 <= b.x0 and b.x1 <= g1 + 0.05 for g0, g1 in spans), (b.x0, b.x1)
            assert any(s0 - 0.05 <= b.x0 and b.x1 <= s1 + 0.05 for s0, s1 in summary["outage_windows_s"])
            shaded_total += b.x1 - b.x0
    assert shaded_total > 0
    # An outage window after the last RTK-fixed epoch is not shaded at all.
    last = max(arrays[n]["t"][-1] for n in ("rtk_outages", "degraded_outages")) - t0
    assert any(s0 > last for s0, _ in summary["outage_windows_s"])
    assert all(p.get_window_extent().transformed(ax.transData.inverted()).x0 < last
               for ax in fig.axes for p in ax.patches)


def test_spans_splits_at_gaps():
    from quatnav.experiments.walk_rtk import _spans
    t = np.r_[np.arange(0, 5, 0.25), np.arange(8, 9, 0.25)]
    assert _spans(t) == [(0.0, 4.75), (8.0, 8.75)]
    assert _spans(np.array([])) == []


def _broad_results(rate=100.0, n=3000):
    rng = np.random.default_rng(0)
    mov = np.ones(n, bool)
    mov[:500] = mov[-400:] = False
    small = np.abs(0.7 + 0.1 * rng.standard_normal(n))
    big = np.abs(30 + 5 * rng.standard_normal(n))
    res = {"qekf": {"total": 0.7, "series_total_deg": small, "series_movement": mov, "series_rate_hz": rate},
           "peer": {"total": 30.0, "series_total_deg": big, "series_movement": mov, "series_rate_hz": rate}}
    return {"algorithms": ["qekf", "peer"],
            "trials": {"01_synthetic": {"groups": ["g"], "results": res}},
            "groups": {"g": {"trials": ["01_synthetic"], "qekf": {"total": 0.7}, "peer": {"total": 30.0}}},
            "mean": {"qekf": {"total": 0.7}, "peer": {"total": 30.0}}}


def test_broad_figures_from_results(tmp_path):
    from quatnav.evaluation.evaluate import plot_results
    files = plot_results(_broad_results(), tmp_path / "plots")
    assert [f.name for f in files] == ["error_01_synthetic.png", "groups_total_rmse.png"]
    for f in files:
        _png_ok(f)


def test_broad_per_trial_figure_log_axis(tmp_path, monkeypatch):
    """The per-trial figure is on a log axis whose range holds both a 0.7 deg and a 30 deg curve."""
    import quatnav._plotting as P
    from quatnav.evaluation.evaluate import plot_results
    made = []
    real = P.figure
    monkeypatch.setattr(P, "figure", lambda *a, **k: made.append(real(*a, **k)) or made[-1])
    plot_results(_broad_results(), tmp_path)
    ax = made[0].axes[0]
    assert ax.get_yscale() == "log"
    lo, hi = ax.get_ylim()
    assert lo < 0.5 and hi > 35
    _legends_outside(made[0])
    _legends_outside(made[1])


def test_broad_figure_on_a_real_trial(data_dir, tmp_path):
    from quatnav.evaluation import evaluate
    src = data_dir / "broad"
    trial = src / "02_undisturbed_slow_rotation_B.mat"
    if not trial.exists():
        pytest.skip(f"{trial} not found")
    d = tmp_path / "broad"
    d.mkdir()
    (d / trial.name).symlink_to(trial)
    if (src / "trials.json").exists():
        (d / "trials.json").symlink_to(src / "trials.json")
    res = evaluate.evaluate(d, filters=("qekf",), peers=(), keep_series=True)
    files = evaluate.plot_results(res, tmp_path / "plots")
    assert any(f.name.startswith("error_02_") for f in files)
    for f in files:
        _png_ok(f)


def test_scenario_overview_unwraps_yaw(tmp_path):
    """paper001_constant_turn turns through +/-180 deg twice: the yaw line has no jump."""
    pytest.importorskip("quatnav.sim")
    import matplotlib.pyplot as plt
    from quatnav.sim import make_scenario, plot_scenario
    s = make_scenario("paper001_constant_turn", seed=0)
    assert np.any(np.abs(np.diff(s.truth.rpy[:, 2])) > np.pi)  # the raw yaw does wrap
    fig = plot_scenario(s, tmp_path / "turn.png")
    try:
        _png_ok(tmp_path / "turn.png")
        att = fig.axes[2]
        yaw = next(line for line in att.get_lines() if line.get_label() == "yaw")
        assert np.max(np.abs(np.diff(yaw.get_ydata()))) < 5.0
        assert np.ptp(yaw.get_ydata()) > 600  # two turns unwrapped
        _legends_outside(fig)
    finally:
        plt.close(fig)


# --- the figures of ins run, ahrs run and the demo ---------------------------------------------------
def _spy(monkeypatch):
    """Record every figure saved (Figure.savefig) in a list."""
    import matplotlib.figure
    figs = []
    save = matplotlib.figure.Figure.savefig

    def spy(fig, path, *a, **k):
        figs.append(fig)
        return save(fig, path, *a, **k)
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", spy)
    return figs


def _angle_axes_ok(ax):
    """No line of the angles axes jumps by more than 180 deg between neighbouring points (the
    stroke of a wrap through +-180), the axis stays within +-190 deg, and every band (3 sigma)
    lies within +-180 deg."""
    for line in ax.get_lines():
        y = np.asarray(line.get_ydata(), float)
        assert not (np.abs(np.diff(y)) > 180.0).any(), line.get_label()
    lo, hi = ax.get_ylim()
    assert -190.0 <= lo and hi <= 190.0
    for band in ax.collections:
        for path in band.get_paths():
            assert np.abs(path.vertices[:, 1]).max() <= 180.0 + 1e-9


def test_ins_run_figure(tmp_path, monkeypatch):
    """A walk on an absolute clock whose heading wraps through +-180 and starts unknown (its
    3-sigma band wider than the circle): the time axis in seconds since the start (no offset like
    "+1.756e9"), the angles without wrap strokes, the bands clipped, x/y/z on the bias panels."""
    import quatnav
    from quatnav import io
    from quatnav.pipeline import run_ins
    from quatnav.pipeline.figures import plot_nav
    from quatnav.sim.scenarios import make_scenario
    s = make_scenario("paper004_walk", seed=0)
    g = s.gps
    t0 = 1.756402e9
    log = io.Log(source="walk", imu=io.Imu(t=t0 + s.imu.t, gyr=s.imu.gyro, acc=s.imu.accel),
                 gnss=io.Gnss(t=t0 + g.t_valid, lat=g.lat, lon=g.lon, h=g.h, vel_n=g.v_n))
    run = run_ins(log)
    r = run.result
    # a heading through +-180 deg and a yaw sigma of 2 rad in the first 10 s (as before a course)
    r.quat[:] = quatnav.core.quaternion.mul(np.array([0.0, 0.0, 0.0, 1.0]), r.quat)
    r.sigma[r.t < t0 + 20.0, 8] = 2.0
    figs = _spy(monkeypatch)
    plot_nav(tmp_path / "nav.png", r, run.rows, run.inputs.gnss)
    _png_ok(tmp_path / "nav.png", 1000, 800)
    fig = figs[-1]
    by_label = {ax.get_ylabel(): ax for ax in fig.axes}
    att = by_label["attitude [deg] (band: 3 sigma)"]
    yaw = np.degrees(r.euler[run.rows, 2])
    assert (np.abs(np.diff(yaw)) > 180.0).any()  # it wraps: the test can fail
    _angle_axes_ok(att)
    for label in ("gyro bias [deg/h]", "accelerometer bias [m/s^2]"):
        leg = by_label[label].get_legend()
        assert [x.get_text() for x in leg.get_texts()] == ["x", "y", "z"], label
    x = att.get_xlabel()
    assert x.startswith("time since t = 1756402") and x.endswith("[s]"), x
    fig.canvas.draw()
    ticks = [tl.get_text() for tl in att.get_xticklabels()]
    assert not any("e9" in tl or "+" in tl for tl in ticks) and att.xaxis.get_offset_text().get_text() == "", ticks


def test_ahrs_run_figure(tmp_path, monkeypatch):
    """ahrs run's figure: angles without wrap strokes, x/y/z on the gyro bias."""
    import quatnav
    from quatnav import io
    from quatnav.pipeline.figures import plot_attitude
    from quatnav.sim.scenarios import make_scenario
    s = make_scenario("handheld_marg", seed=0)
    res = quatnav.QuaternionEKF().run(s.imu.gyro, s.imu.accel, t=1.756402e9 + s.imu.t)
    figs = _spy(monkeypatch)
    plot_attitude(res, io.Log(), tmp_path / "a.png")
    _png_ok(tmp_path / "a.png")
    ax = figs[-1].axes
    assert (np.abs(np.diff(np.degrees(res.euler[:, 2]))) > 180.0).any()
    _angle_axes_ok(ax[0])
    assert [x.get_text() for x in ax[1].get_legend().get_texts()] == ["x", "y", "z"]
    assert ax[-1].get_xlabel().startswith("time since t = ")


def test_demo_figure_reads_at_page_width(tmp_path, monkeypatch):
    """One column 11 in wide (two columns made it 17 in: on a 750 px page its text was 5 px
    high), no text smaller than 7.5 points."""
    import matplotlib.text
    import quatnav
    from quatnav import demo
    d = demo.rotation_scenario(n=1500)
    res = {"QuaternionEKF": {"result": quatnav.QuaternionEKF().run(d.gyr, d.acc, d.mag, dt=d.dt)}}
    figs = _spy(monkeypatch)
    demo._plot(d, res, None, None, tmp_path / "demo.png")
    fig = figs[-1]
    assert fig.get_size_inches()[0] <= 11.0
    sizes = [t.get_fontsize() for t in fig.findobj(matplotlib.text.Text) if t.get_text().strip()]
    assert min(sizes) >= 7.5, min(sizes)
