"""End to end: scenario -> IK -> ideal and clearance runs -> files -> figures (issue 4)."""

import time

import numpy as np
import pytest
from typer.testing import CliRunner

import clearance as cl
from clearance.analysis.assembly import assemble
from clearance.cli.main import app
from clearance.io.dataset import load_results
from clearance.pipeline import place_balls_along_reaction, run_scenario
from clearance.scenario import (
    build_mechanisms,
    default_scenario_path,
    load_scenario,
    scenario_to_toml,
    with_overrides,
)


def short(name: str, **extra):
    s = load_scenario(default_scenario_path(name))
    over = {"trajectory.duration": 0.1, "solver.dt_out": 1e-3, "output.figures": False}
    over.update(extra)
    return with_overrides(s, over)


@pytest.fixture(scope="module")
def ups(tmp_path_factory):
    return run_scenario(short("ups_upu"), out_dir=tmp_path_factory.mktemp("ups"), log=None)


def test_ideal_follows_the_prescribed_trajectory(ups):
    """Ideal 4UPS-UPU driven by the IK drives: platform centre on the trajectory to 1e-9 m
    and platform normal to 1e-9 rad (the twist is what the UPU leg imposes)."""
    s = ups.scenario
    _, _, info = build_mechanisms(s)
    f = info.pose_functions()
    r = ups.ideal
    pos = np.array([[f[c](t) for c in "xyz"] for t in r.t])
    assert np.max(np.abs(r.position("platform") - pos)) < 1e-9
    n = r.rotation("platform")[:, :, 2]
    traj = info.platform_trajectory()
    n_target = np.array([traj.normal(t) for t in r.t])
    assert np.max(np.linalg.norm(n - n_target, axis=1)) < 1e-9


def test_a_fast_periodic_trajectory_is_followed(tmp_path):
    """A 20 Hz rest-to-rest motion: the IK samples each period 50 times (0.02 s spacing
    would land on whole periods and drive a platform that barely moves), so the ideal
    platform follows it to the drive splines' error (~(2 pi / 50)^6 of the amplitude)."""
    s = short("ups_upu", **{"trajectory.period": 0.05})
    o = run_scenario(s, out_dir=tmp_path, log=None)
    f = build_mechanisms(s)[2].pose_functions()
    r = o.ideal
    pos = np.array([[f[c](t) for c in "xyz"] for t in r.t])
    assert np.ptp(pos[:, 2]) > 0.029  # it moves: z swings through its 0.03 m amplitude
    assert np.max(np.abs(r.position("platform") - pos)) < 1e-6


def test_clearance_run_outputs_and_round_trip(ups):
    r = ups.clearance
    assert ups.ideal.success and r.success
    for name in ("S_1", "S_3"):
        assert np.max(r.penetration(name)) < 2e-5  # within clearance + micrometres
    s = ups.summary
    assert set(s["joints"]) == {"S_1", "S_3"}
    assert s["clearance"]["energy_residual_relative"] < 1e-6
    nc = ups.files[0]
    data = load_results(nc)
    assert set(data) == {"ideal", "clearance"}
    assert data.attrs["scenario"] == scenario_to_toml(ups.scenario)
    assert data.attrs["clearance_version"] == cl.__version__
    np.testing.assert_array_equal(
        data["clearance"]["penetration"].values[:, 0], r.penetration("S_1")
    )


def test_option_b_places_the_ball_along_the_ideal_reaction():
    s = short("ups_upu", **{"clearance.initial": "reaction"})
    ideal, clr, info = build_mechanisms(s)
    ci = cl.compile_mechanism(ideal)
    y0 = cl.initial_state(ci)
    ri = cl.simulate(ci, 1e-6, t_out=np.array([0.0, 1e-6]))
    cc = cl.compile_mechanism(clr)
    y = np.zeros(cc.ny)
    y[: cc.nq + cc.nv] = y0[: ci.nq + ci.nv]
    yb = place_balls_along_reaction(clr, ri, y, info.clearance_joints)
    r = cl.simulate(cc, 1e-6, t_out=np.array([0.0]), y0=yb)
    for name in info.clearance_joints:
        e = r.eccentricity(name)[0]
        assert np.linalg.norm(e) == pytest.approx(0.3e-3, rel=1e-9)
    assert np.max(np.abs(assemble(cc, yb) - yb)) < 1e-12  # consistent with all rows


def test_ups_upu_static_actuator_forces_equal_virtual_work():
    """At rest (home lengths held), the actuator forces equal the derivative of the
    potential energy of the assembled mechanism with respect to the leg lengths (virtual
    work, an independent oracle: F_k = dV/dl_k by central differences of assembly)."""
    from clearance.mechanisms.ups_upu import home_leg_lengths, ups_upu_ideal

    home = list(home_leg_lengths())
    c = cl.compile_mechanism(ups_upu_ideal(drives=home))  # the factory default drives move
    r = cl.simulate(c, 1e-3, t_out=np.array([0.0]))
    F = np.array([r.actuator_force(f"drive_{k}")[0] for k in range(1, 6)])
    assert np.max(np.abs(r.v[0])) < 1e-12  # at rest

    def V(lengths):
        cc = cl.compile_mechanism(ups_upu_ideal(drives=lengths))
        y = assemble(cc, cl.initial_state(c))  # same bodies and layout, other lengths
        g = np.array(cc.mechanism.gravity)
        return -sum(
            b.mass * g @ y[7 * k : 7 * k + 3] for k, b in enumerate(cc.mechanism.bodies.values())
        )

    h = 1e-6
    for k in range(5):
        lp, lm = list(home), list(home)
        lp[k] += h
        lm[k] -= h
        dV = (V(lp) - V(lm)) / (2 * h)
        assert F[k] == pytest.approx(dV, rel=1e-5, abs=1e-6 * np.max(np.abs(F)))


def test_universal_pair_clearance_runs_from_the_ideal_start(tmp_path):
    """A clearance in a universal joint's pair adds the cross as a body: the clearance run
    starts every other body where the ideal run starts (the cross is placed by the initial
    assembly), ball placement along the reaction skips it, the file round-trips."""
    u1 = {
        "pair": "i",
        "cross_mass": 0.05,
        "cross_inertia": [2e-5, 2e-5, 3e-5],
        "journal_radius": 0.006,
        "radial_clearance": 1e-4,
    }
    s = short("ups_upu", **{"trajectory.duration": 0.02})
    s = with_overrides(s, {"clearance.joints.U_1": u1})
    o = run_scenario(s, out_dir=tmp_path, log=None)
    ri, rc = o.ideal, o.clearance
    assert ri.success and rc.success, rc.message
    assert "U_1.cross" in rc.compiled.body_names and set(o.summary["joints"]) >= {"U_1.i"}
    for b in ri.compiled.body_names:
        np.testing.assert_allclose(rc.q[0, rc.compiled.q_slice(b)], ri.q[0, ri.compiled.q_slice(b)])
    assert np.linalg.norm(rc.eccentricity("U_1.i")[0]) < 1e-12  # the journal starts centred
    assert np.max(rc.penetration("U_1.i")) < 2e-5
    data = load_results(o.files[0])
    assert "U_1.i" in data["clearance"]["clearance"].values
    _, clr, info = build_mechanisms(s)
    assert info.clearance_joints == ("S_1", "S_3", "U_1.i")
    y0 = np.concatenate(
        (rc.q[0], rc.v[0], np.zeros(rc.compiled.ny - rc.q.shape[1] - rc.v.shape[1]))
    )
    yb = place_balls_along_reaction(clr, ri, y0, info.clearance_joints)  # S_1, S_3 only
    r = cl.simulate(rc.compiled, 1e-6, t_out=np.array([0.0]), y0=yb)
    assert np.linalg.norm(r.eccentricity("S_1")[0]) == pytest.approx(0.3e-3, rel=1e-9)
    assert np.linalg.norm(r.eccentricity("U_1.i")[0]) < 1e-9


def test_run_writes_the_lean_default_and_the_outputs_asked_for(ups, tmp_path):
    """Default file: the platform, actuators, energy and clearance channels at full
    resolution, equal to the results in memory; `outputs` adds groups."""
    data = load_results(ups.files[0])
    for g, r in (("ideal", ups.ideal), ("clearance", ups.clearance)):
        ds = data[g]
        assert list(ds["body"].values) == ["platform"] and ds.sizes["time"] == r.t.size
        assert "multiplier" not in ds and "reaction_force" not in ds
        np.testing.assert_array_equal(ds["position"].values[:, 0], r.position("platform"))
        np.testing.assert_array_equal(ds["actuator_force"].values, r.driver_force)
    np.testing.assert_array_equal(
        data["clearance"]["contact_force"].sel(clearance="S_1").values,
        ups.clearance.contact_force("S_1"),
    )
    s = short("ups_upu", **{"trajectory.duration": 0.01, "output.outputs": ["reactions"]})
    o = run_scenario(s, out_dir=tmp_path, log=None)
    ds = load_results(o.files[0])["clearance"]
    np.testing.assert_array_equal(ds["reaction_force"].values, o.clearance.reaction_force)
    assert "multiplier" not in ds
    o = run_scenario(s, out_dir=tmp_path / "all", outputs=("all",), log=None)
    ds = load_results(o.files[0])["clearance"]
    assert ds.sizes["body"] == len(o.clearance.compiled.body_names) and "multiplier" in ds


def test_sps_cu_scenario_runs_lumped(tmp_path):
    o = run_scenario(short("sps_cu"), out_dir=tmp_path, log=None)
    assert o.ideal.success and o.clearance.success
    assert np.max(o.clearance.penetration("SB_1")) < 2e-5
    assert o.files[0].exists()


def test_cli_run_plot_export(tmp_path):
    s = short("ups_upu", **{"output.figures": True})
    path = tmp_path / "s.toml"
    path.write_text(scenario_to_toml(s))
    runner = CliRunner()
    r = runner.invoke(app, ["run", str(path), "--out", str(tmp_path / "o"), "--timings"])
    assert r.exit_code == 0, r.output
    assert "summary of" in r.output and "S_1: peak F_N" in r.output
    for stage in ("inverse_kinematics", "clearance", "write", "figures", "total"):
        assert f"\n  {stage} " in r.output, stage
    assert not list((tmp_path / "o" / "figures").glob("*.pdf"))  # only the format asked for
    r = runner.invoke(app, ["run", str(path), "--outputs", "bodies,forces"])
    assert r.exit_code == 2 and "unknown output 'forces'" in r.output
    nc = tmp_path / "o" / f"{s.name}.nc"
    assert nc.exists() and (tmp_path / "o" / "figures" / "contact_force.png").exists()
    r = runner.invoke(app, ["plot", str(nc), "--out", str(tmp_path / "f2"), "--format", "png"])
    assert r.exit_code == 0 and (tmp_path / "f2" / "platform_velocity.png").exists()
    r = runner.invoke(app, ["export", str(nc), "--out", str(tmp_path / "x")])
    assert r.exit_code == 0 and (tmp_path / "x" / f"{s.name}.mat").exists()
    r = runner.invoke(app, ["export", str(tmp_path / "missing.nc")])
    assert r.exit_code == 2 and "no such result file" in r.output
    bad = tmp_path / "bad.toml"
    bad.write_text(scenario_to_toml(s).replace("rtol = 1e-06", "rtol = -1.0"))
    r = runner.invoke(app, ["run", str(bad)])
    assert r.exit_code == 2 and "solver.rtol" in r.output


def test_sps_cu_lumped_actuator_forces_match_two_body_ik_model(tmp_path):
    """The lumped run's recovered actuator forces (physics.md i) equal the two-body model's
    driver forces for the same lengths (the ideal runs; lumped is exact for axial limbs)."""
    s = short("sps_cu")
    o = run_scenario(s, out_dir=tmp_path, log=None)
    _, _, info = build_mechanisms(s)
    from clearance.analysis.ik import drives_from_ik

    _, _, info2 = build_mechanisms(s, drives=drives_from_ik(o.ik))
    r2 = cl.simulate(info2.ik_mechanism, s.trajectory.duration, dt_out=1e-3, rtol=1e-10, atol=1e-12)
    r1 = o.ideal
    assert r1.driver_names == tuple(f"drive_{k}" for k in range(1, 5))
    n = min(r1.t.size, r2.t.size)
    F1 = r1.driver_force[:n]
    F2 = np.column_stack([r2.actuator_force(f"drive_{k}") for k in range(1, 5)])[:n]
    assert np.max(np.abs(F1 - F2)) < 1e-4 * np.max(np.abs(F2))


def test_compile_notice_says_when_kernels_compile():
    """A compile is announced at once, with progress, and summed up; loading from the
    cache (or an already compiled function) says nothing."""
    import numba

    from clearance.pipeline import CompileNotice

    @numba.njit(cache=False)
    def fresh(x):
        return x + 1

    lines: list[str] = []
    with CompileNotice(lines.append, every=0.0) as notice:
        fresh(1)
        fresh(2.0)
    assert notice.compiled == 2
    assert "compiling the kernels (one time" in lines[0]
    assert any("2 functions compiled" in ln for ln in lines)
    assert lines[-1].strip().startswith("compiled 2 functions in")
    lines.clear()
    with CompileNotice(lines.append) as notice:
        fresh(3)
    assert notice.compiled == 0 and lines == []


def test_warmup_leaves_nothing_to_compile(tmp_path):
    from clearance.pipeline import CompileNotice, warmup

    out = warmup(log=None)
    assert out["cache"] and out["functions"] >= 0
    with CompileNotice(None) as notice:
        for name in ("ups_upu", "sps_cu"):
            s = short(
                name,
                **{"trajectory.duration": 0.005, "solver.method": "rk4", "solver.step": 1e-5},
            )
            run_scenario(s, out_dir=tmp_path / name, log=None)
    assert notice.compiled == 0


def test_reuse_ideal_between_clearance_only_variations(tmp_path):
    """A case that changes only clearance parameters reuses the previous case's inverse
    kinematics and ideal run and gets exactly the results of running it afresh; a case
    with another trajectory does not reuse them."""
    import clearance.pipeline as P

    base = short("ups_upu", **{"trajectory.duration": 0.02})
    wide = with_overrides(base, {"clearance.joints.S_1.radial_clearance": 0.4e-3})
    P._IDEAL_MEMO.clear()
    first = run_scenario(base, out_dir=tmp_path / "a", reuse_ideal=True, log=None)
    assert "reused_ideal" not in first.timings
    again = run_scenario(wide, out_dir=tmp_path / "b", reuse_ideal=True, log=None)
    assert again.timings["reused_ideal"] == 1.0 and again.ideal is first.ideal
    fresh = run_scenario(wide, out_dir=tmp_path / "c", log=None)
    for name in ("q", "v", "lam", "contact"):
        a, b = getattr(again.clearance, name), getattr(fresh.clearance, name)
        np.testing.assert_array_equal(a, b)
    assert again.summary["deviation_rms"] == fresh.summary["deviation_rms"]
    other = with_overrides(wide, {"trajectory.duration": 0.03})
    third = run_scenario(other, out_dir=tmp_path / "d", reuse_ideal=True, log=None)
    assert "reused_ideal" not in third.timings and third.ideal is not first.ideal


def test_concurrent_runs_equal_the_sequential_pipeline(tmp_path):
    """run_scenario integrates the ideal run in a second thread while the clearance run
    starts from a short run's first sample: the same numbers, bit for bit, as the plain
    sequence (full ideal run, its first sample placing the balls along the reaction,
    then the clearance run)."""
    from clearance.analysis.ik import drives_from_ik
    from clearance.pipeline import _start_from

    s = short("ups_upu", **{"trajectory.duration": 0.03, "clearance.initial": "reaction"})
    out = run_scenario(s, out_dir=tmp_path, log=None)
    ideal, clr, info = build_mechanisms(s, drives=drives_from_ik(out.ik))
    kw = info.simulate_kwargs
    r_i = cl.simulate(cl.compile_mechanism(ideal), info.t_end, **kw)
    cc = cl.compile_mechanism(clr)
    y0 = place_balls_along_reaction(clr, r_i, _start_from(r_i, cc, ideal, s), info.clearance_joints)
    r_c = cl.simulate(cc, info.t_end, y0=y0, **kw)
    assert out.clearance.stats["nevents"] > 0  # the balls move off their start
    for name in ("t", "q", "v", "a", "lam", "contact"):
        np.testing.assert_array_equal(getattr(out.ideal, name), getattr(r_i, name))
        np.testing.assert_array_equal(getattr(out.clearance, name), getattr(r_c, name))
    assert out.timings["ideal"] > 0 and out.timings["clearance"] > 0


def test_cold_compile_children_leave_the_results_unchanged(tmp_path, monkeypatch):
    """With a cold cache (forced here), compile children are forked and joined; the run
    is the same bit for bit. The children then find every kernel cached, so this stays
    fast; bench/bench_run.py --cold measures a real cold start."""
    import threading

    import clearance.pipeline as P

    if threading.active_count() > 1:  # by design, ColdCompile forks no threaded process
        pytest.skip("threads of an earlier test (a Dask client) still run in this process")
    s = short("ups_upu", **{"trajectory.duration": 0.01})
    plain = run_scenario(s, out_dir=tmp_path / "a", log=None)
    started = []
    real_init = P.ColdCompile.__init__

    def spy(self, *a, **k):
        real_init(self, *a, **k)
        started.append(self.child is not None)

    monkeypatch.setattr(P, "_kernels_cached", lambda: False)
    monkeypatch.setattr(P.ColdCompile, "__init__", spy)
    cold = run_scenario(s, out_dir=tmp_path / "b", log=None)
    assert started == [True]
    for name in ("q", "v", "lam", "contact"):
        a, b = getattr(plain.clearance, name), getattr(cold.clearance, name)
        np.testing.assert_array_equal(a, b)
    monkeypatch.setattr(P, "_kernels_cached", lambda: True)
    run_scenario(s, out_dir=tmp_path / "c", log=None)
    assert started == [True, False]  # a warm cache forks nothing


def test_cold_compile_survives_a_child_that_dies_silently(tmp_path, monkeypatch):
    """A compile child killed before it says the contact kernels are ready (OOM killer,
    os._exit) costs the parent no wait: it compiles what is missing and the run is the
    same."""
    import os
    import threading

    import clearance.pipeline as P

    if threading.active_count() > 1:  # by design, ColdCompile forks no threaded process
        pytest.skip("threads of an earlier test (a Dask client) still run in this process")
    s = short("ups_upu", **{"trajectory.duration": 0.01})
    plain = run_scenario(s, out_dir=tmp_path / "a", log=None)
    monkeypatch.setattr(P, "_kernels_cached", lambda: False)
    monkeypatch.setattr(P, "_compile_contact_kernels", lambda cc, method, ready: os._exit(0))
    t0 = time.perf_counter()
    cold = run_scenario(s, out_dir=tmp_path / "b", log=None)
    assert time.perf_counter() - t0 < 30  # not the 10-minute ceiling of a lost signal
    np.testing.assert_array_equal(plain.clearance.q, cold.clearance.q)


def test_a_failing_clearance_run_leaves_no_ideal_thread_and_keeps_its_ideal_run(
    tmp_path, monkeypatch
):
    """The clearance run fails while the ideal one integrates in its thread: the error
    comes out, the thread is joined (nothing keeps integrating behind the caller), and a
    retry reuses the ideal run."""
    import threading

    import clearance.pipeline as P

    s = short("ups_upu", **{"trajectory.duration": 0.02})
    P._IDEAL_MEMO.clear()

    def broken(*a, **k):
        raise RuntimeError("no start (simulated)")

    monkeypatch.setattr(P, "_start_from", broken)
    with pytest.raises(RuntimeError, match="simulated"):
        run_scenario(s, out_dir=tmp_path / "a", reuse_ideal=True, log=None)
    assert not [t for t in threading.enumerate() if t.name.startswith("clearance-")]
    monkeypatch.undo()
    again = run_scenario(s, out_dir=tmp_path / "b", reuse_ideal=True, log=None)
    assert again.timings["reused_ideal"] == 1.0


def test_a_figure_failure_keeps_the_result_file(tmp_path, monkeypatch):
    """Figures are set up before the NetCDF write (to draw while it writes); a failure
    there still writes the results first, then raises."""
    import clearance.plot as plot

    def broken(*a, **k):
        raise KeyError("no figure for this kind (simulated)")

    monkeypatch.setattr(plot, "start_figures", broken)
    s = short("ups_upu", **{"trajectory.duration": 0.01, "output.figures": True})
    with pytest.raises(KeyError, match="simulated"):
        run_scenario(s, out_dir=tmp_path, log=None)
    back = load_results(tmp_path / f"{s.name}.nc")
    assert back["clearance"].sizes["time"] > 1


def test_deferred_write_writes_later_and_counts_in_the_total(tmp_path):
    s = short("ups_upu", **{"trajectory.duration": 0.01})
    out = run_scenario(s, out_dir=tmp_path, defer_write=True, log=None)
    assert out.files == [] and not list(tmp_path.glob("*.nc"))
    total = out.timings["total"]
    files = out.write()
    assert files and files[0].exists() and out.write() == files  # once
    assert out.timings["write"] > 0 and out.timings["total"] > total


def test_warm_worker_is_free_once_a_scenario_ran(monkeypatch, tmp_path):
    """A study worker warms up with a tiny run, unless this process already ran one."""
    import clearance.pipeline as P
    from clearance.sweep.run import warm_worker

    monkeypatch.setattr(P, "_RAN", False)
    assert warm_worker() > 0.0 and P._RAN
    assert warm_worker() == 0.0


@pytest.mark.parametrize(
    "name,stem",
    [("ups_upu", "ups_upu"), ("../../x", "_.._x_"), ("a/b:c", "a_b_c_"), ("x" * 300, None)],
)
def test_result_files_stay_in_their_folder_under_a_usable_name(tmp_path, name, stem):
    """The scenario name names the files: path separators cannot lead outside the output
    folder, and a 300-character name still makes a file (it failed after the run)."""
    from clearance.io.files import STEM_BYTES

    s = short("ups_upu", **{"trajectory.duration": 0.01, "scenario.name": name})
    out = tmp_path / "deep" / "out"
    o = run_scenario(s, out_dir=out, log=None)
    (nc,) = [f for f in o.files if f.suffix == ".nc"]
    assert nc.parent == out and nc.exists()
    assert len(nc.stem.encode()) <= STEM_BYTES
    if stem is not None:  # a changed name gains a hash of the original: a_b_c_1a2b3c4d
        assert nc.stem == stem or (nc.stem.startswith(stem) and len(nc.stem) == len(stem) + 8)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deep"]  # nothing beside


def test_names_that_differ_keep_different_files():
    from clearance.io.files import output_stem

    names = ["a/b", "a:b", "a_b", "a\\b", ".a_b", "x" * 300, "x" * 299 + "y"]
    stems = [output_stem(n) for n in names]
    assert len(set(stems)) == len(names), stems
    assert output_stem("a_b") == "a_b" and output_stem("ups_upu") == "ups_upu"


def test_an_unwritable_output_folder_is_refused_before_the_run(tmp_path):
    from clearance.scenario import ScenarioError

    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    s = short("ups_upu", **{"trajectory.duration": 0.01})
    with pytest.raises(ScenarioError) as err:
        run_scenario(s, out_dir=blocker / "out", log=lambda m: pytest.fail(f"ran: {m}"))
    assert err.value.field == "output.folder" and "cannot write results there" in str(err.value)


def test_outputs_beyond_the_memory_budget_are_refused_before_anything_runs(monkeypatch, tmp_path):
    """dt_out = 1e-9 over 2 s asked ~110 GiB and died in a MemoryError after the inverse
    kinematics; now the estimate refuses it at once, naming the interval that fits."""
    from clearance.integrate.simulate import memory_budget, sample_bytes
    from clearance.scenario import ScenarioError

    s = short("ups_upu", **{"trajectory.duration": 2.0, "solver.dt_out": 1e-9})
    said = []
    with pytest.raises(ScenarioError) as err:
        run_scenario(s, out_dir=tmp_path, log=said.append)
    e = err.value
    assert e.field == "solver.dt_out" and e.value == 1e-9
    assert "GiB" in e.allowed and "output interval of at least" in e.allowed
    assert not any("inverse kinematics" in m for m in said)
    # the API: the same estimate; its numbers are the arrays simulate would allocate
    ideal, clr, info = build_mechanisms(s)
    c = cl.compile_mechanism(clr)
    monkeypatch.setenv("CLEARANCE_MEMORY_BUDGET", "0.0009765625")  # 1 MiB
    assert memory_budget() == 2**20
    n_fit = 2**20 // sample_bytes(c)
    small = {"max_events": 100}  # the default event log alone takes 5 MB
    r = cl.simulate(c, 1e-3, t_out=np.linspace(0.0, 1e-3, n_fit - 10), **small)
    assert r.t.size == n_fit - 10
    with pytest.raises(cl.ModelError, match="memory budget") as err:
        cl.simulate(c, 1e-3, dt_out=1e-3 / (n_fit + 10), **small)
    # the interval the message suggests does fit
    fits = float(err.value.allowed.split("at least ")[1].split(" s")[0])
    assert cl.simulate(c, 1e-3, dt_out=fits, **small).t.size <= n_fit


def test_sample_bytes_counts_what_a_result_holds_per_sample():
    """The memory estimate's bytes per sample (`sample_bytes`) against the arrays a Result
    really holds per sample (the increment between two run lengths): within 20 %, so that a
    new per-sample output cannot slip past the estimate."""
    from clearance.integrate.simulate import sample_bytes

    _, clr, _ = build_mechanisms(short("ups_upu"))
    c = cl.compile_mechanism(clr)

    def held(r):
        arrays = [v for v in vars(r).values() if isinstance(v, np.ndarray)]
        arrays += [x for v in vars(r).values() if isinstance(v, dict) for x in v.values()]
        return sum(a.nbytes for a in arrays if isinstance(a, np.ndarray))

    r1, r2 = (cl.simulate(c, t, dt_out=1e-4) for t in (0.005, 0.01))
    per = (held(r2) - held(r1)) / (r2.t.size - r1.t.size)
    assert sample_bytes(c) <= per <= 1.2 * sample_bytes(c), (per, sample_bytes(c))
