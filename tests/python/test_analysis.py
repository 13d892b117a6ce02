"""Analysis functions on synthetic data with known answers."""
import numpy as np
import pytest

from conftest import cube_lattice
from lem_tools import analysis

PAPER_PHASES = {"E_p": 3.0, "E_m": 1.0, "E_pp": 1.0, "E_pm": 1.0, "sigma_p": 0.01}


def test_tail_exponent_recovers_beta_of_a_sampled_exponential_tail():
    rng = np.random.default_rng(1)
    beta = 1.6
    body = rng.uniform(-1.0, 1.0, 30000)                    # below the tail start
    tail = analysis.TAIL_START + rng.exponential(1 / beta, 20000)
    fit = analysis.tail_exponent(np.concatenate([body, tail]))
    assert fit["tail_nodes"] == 20000
    # the ML estimate has a relative spread 1/sqrt(n) = 0.7 %
    assert fit["beta"] == pytest.approx(beta, rel=0.03)
    assert fit["beta_histogram_fit"] == pytest.approx(beta, rel=0.15)


def test_tail_exponent_needs_enough_tail_nodes():
    s = np.concatenate([np.zeros(1000), 1.5 * np.ones(analysis.MIN_TAIL_NODES - 1)])
    assert analysis.tail_exponent(s) is None


def eq10(rho, a, k):
    return a * rho * (2 * analysis.RHO_FILLED - rho) / (1 - k * rho)


def test_eq10_fit_recovers_a_and_k():
    rho = np.repeat([0.06, 0.1, 0.13, 0.17, 0.22, 0.28], 3)
    fit = analysis.fit_eq10(rho, eq10(rho, 0.3, 2.5))
    assert fit["A"] == pytest.approx(0.3, rel=1e-6)
    assert fit["k"] == pytest.approx(2.5, rel=1e-6)
    assert fit["rms_relative_residual"] < 1e-6
    assert fit["points"] == len(rho)


def test_eq10_fit_with_noise():
    rng = np.random.default_rng(2)
    rho = np.repeat([0.06, 0.1, 0.13, 0.17, 0.22, 0.28], 9)
    strength = eq10(rho, 0.3, 2.5) * (1 + 0.01 * rng.standard_normal(rho.size))
    fit = analysis.fit_eq10(rho, strength)
    assert fit["A"] == pytest.approx(0.3, rel=0.05)
    assert fit["k"] == pytest.approx(2.5, rel=0.05)
    assert fit["rms_relative_residual"] == pytest.approx(0.01, rel=0.3)


def test_eq10_fit_needs_two_matrix_fractions():
    assert analysis.fit_eq10([0.13, 0.13], [0.2, 0.3]) is None


def test_eq14_frontier_is_where_k_c_r_reaches_the_limit():
    for e_eff in (0.05, 0.2, 0.6):
        ratio = analysis.eq14_frontier(e_eff, PAPER_PHASES)
        assert analysis.k_c_r_eq14(e_eff, ratio, PAPER_PHASES) == \
            pytest.approx(analysis.K_DAMAGE_LIMIT, rel=1e-12)


def test_k_c_r_eq14_value():
    # sqrt(0.5 * 3 / 1 * 0.6) = sqrt(0.9)
    assert analysis.k_c_r_eq14(0.5, 0.6, PAPER_PHASES) == pytest.approx(0.9 ** 0.5)


def test_share_without_bare_contacts():
    assert analysis.share_without_bare_contacts(5, 30, 10) == 0.25
    assert analysis.share_without_bare_contacts(0, 4, 4) == 0.0  # only bare contacts


def test_group_by_rho_orders_fractions_and_ratios():
    rows = [{"rho_m": 0.2, "sigma_pm_ratio": 1.2}, {"rho_m": 0.1, "sigma_pm_ratio": 0.8},
            {"rho_m": 0.2, "sigma_pm_ratio": 0.4}]
    groups = analysis.group_by_rho(rows)
    assert list(groups) == [0.1, 0.2]
    assert [r["sigma_pm_ratio"] for r in groups[0.2]] == [0.4, 1.2]


def test_hashin_shtrikman_limits():
    assert analysis.hashin_shtrikman(0.3, 1.0) == pytest.approx(1.0)   # one material
    assert analysis.hashin_shtrikman(0.0, 10.0) == pytest.approx(1.0)  # no inclusion
    assert analysis.hashin_shtrikman(1.0, 10.0) == pytest.approx(10.0)  # all inclusion
    stiff, pores = analysis.hashin_shtrikman(0.2, 10.0), analysis.hashin_shtrikman(0.2, 0.0)
    assert 1.0 < stiff < 0.8 + 0.2 * 10.0    # below the Voigt bound
    assert 0.0 < pores < 0.8


def test_node_stress_statistics_of_a_uniform_field():
    coords, volume = cube_lattice(4)
    stress = np.zeros((len(coords), 6))
    stress[:, analysis.ZZ] = 2.0
    stress[:3] = 0.0  # unbonded nodes carry no stress
    statistics, s, loaded, on_face = analysis.node_stress_statistics(
        {"coords": coords, "stress": stress, "volume": volume, "applied": 2.0, "strain": 1e-5})
    assert statistics["nodes"] == 64 and statistics["loaded_nodes"] == 61
    assert loaded.sum() == 61 and np.all(s == 1.0)
    # 61 of 64 equal volumes carry the applied stress
    assert statistics["volume_average_stress_zz"] == pytest.approx(2.0 * 61 / 64)
    assert statistics["volume_average_relative_gap"] == pytest.approx(3 / 64)
    assert statistics["tensile_share"] == 1.0
    assert statistics["tail"] is None  # no node above s = 1
    # the 4 x 4 x 4 grid: 8 of its 64 nodes are off the faces
    assert on_face.size == 61 and (~on_face).sum() == 8
    assert statistics["face_nodes"] == 53


def test_beta_leaves_out_the_nodes_on_the_box_faces():
    # Inside: an exponential tail of exponent 2; on the faces the stresses
    # read twice as high (as the halved Voronoi cells make them): with them
    # the tail is fatter, without them the fit finds 2 again.
    coords, volume = cube_lattice(12)
    rng = np.random.default_rng(5)
    s = np.where(rng.random(len(coords)) < 0.5, rng.uniform(0, 1, len(coords)),
                 1 + rng.exponential(1 / 2.0, len(coords)))
    on_face = analysis.on_box_faces(coords, coords.min(axis=0), coords.max(axis=0))
    assert on_face.sum() == 12 ** 3 - 10 ** 3
    s[on_face] *= 2.0
    stress = np.zeros((len(coords), 6))
    stress[:, analysis.ZZ] = s
    statistics, _, _, _ = analysis.node_stress_statistics(
        {"coords": coords, "stress": stress, "volume": volume, "applied": 1.0, "strain": 1e-5})
    assert statistics["tail"]["beta"] == pytest.approx(2.0, rel=0.08)
    assert statistics["tail_all_nodes"]["beta"] < 0.8 * statistics["tail"]["beta"]
    assert statistics["face_mean_s"] == pytest.approx(2 * s[~on_face].mean(), rel=0.1)


def test_mid_plane_map_takes_the_nearest_node():
    coords = np.array([[0.0, 0.5, 0.5], [1.0, 0.5, 0.5]])
    image, extent = analysis.mid_plane_map(coords, np.array([-1.0, 1.0]), np.zeros(3),
                                           np.ones(3), pixels=10)
    assert image.shape == (10, 10) and extent == (0.0, 1.0, 0.0, 1.0)
    assert np.all(image[:, :5] == -1.0) and np.all(image[:, 5:] == 1.0)


def test_work_split_takes_differences_of_the_cumulative_counts_at_the_peak():
    from lem_tools import work_split
    # Steps 1-4; the peak at step 2; ruptures at steps 1, 2 and 4 (not 3).
    curve = {"step": np.array([1.0, 2, 3, 4]), "strain": np.array([1e-4, 2e-4, 3e-4, 4e-4]),
             "stress_before_norm": np.array([0.1, 0.2, 0.15, 0.1]),
             "solves": np.array([2.0, 5, 5, 9]), "iterations": np.array([20.0, 80, 80, 200]),
             "pc_builds": np.array([1.0, 1, 1, 2]), "elapsed_s": np.array([1.0, 2, 2.5, 4]),
             "broken": np.array([3.0, 7, 7, 10])}
    stages = work_split.split(curve, 2e-4)
    assert stages["to the peak"] == {"solves": 5, "iterations": 80, "pc_builds": 1,
                                     "elapsed_s": 2, "broken": 7, "evaluated_steps": 2,
                                     "rupture_steps": 2}
    assert stages["after the peak"] == {"solves": 4, "iterations": 120, "pc_builds": 1,
                                        "elapsed_s": 2, "broken": 3, "evaluated_steps": 2,
                                        "rupture_steps": 1}


def test_work_split_cuts_the_tail_at_the_first_equilibrium_below_the_fraction():
    from lem_tools import work_split
    # Peak at step 2 (stress 1.0); after it 0.5, 0.08 (the tail starts), 0.12 (still tail).
    curve = {"strain": np.arange(1.0, 6) * 1e-4,
             "stress_norm": np.array([0.6, 1.0, 0.5, 0.08, 0.12]),
             "solves": np.array([1.0, 2, 5, 7, 8]), "iterations": np.array([10.0, 20, 50, 70, 80]),
             "pc_builds": np.ones(5), "elapsed_s": np.arange(1.0, 6),
             "broken": np.array([1.0, 2, 5, 6, 6])}
    stages = work_split.split(curve, 2e-4, tail_fraction=0.1)
    assert list(stages) == ["to the peak", "peak to 0.1 of it", "below 0.1 of the peak"]
    assert stages["peak to 0.1 of it"]["iterations"] == 30
    assert stages["below 0.1 of the peak"]["evaluated_steps"] == 2
    assert stages["below 0.1 of the peak"]["iterations"] == 30
    assert stages["below 0.1 of the peak"]["rupture_steps"] == 1


def test_tail_must_be_a_fraction_below_one():
    from lem_tools import work_split
    from lem_tools.errors import ToolError
    assert work_split.tail_fraction(0.1) == 0.1
    for bad in (-0.1, 1.0, float("nan")):
        with pytest.raises(ToolError, match="--tail"):
            work_split.tail_fraction(bad)


def test_floor_charges_one_closing_solve_per_rupture_step_of_a_stage():
    from lem_tools import work_split
    # Peak at step 2.  After it: step 3 one batch, one solve (40 its); step 4
    # three cycles, five solves (200 its); step 5 one batch, one solve (60
    # its); step 6 no rupture (a solve of 10 its).  Closing solve: median of
    # 40 and 60; 310 its in 31 s after the peak.
    curve = {"strain": np.arange(1.0, 7) * 1e-4,
             "stress_norm": np.array([0.5, 1.0, 0.9, 0.8, 0.7, 0.6]),
             "cycles": np.array([1.0, 1, 1, 3, 1, 0]),
             "solves": np.array([1.0, 2, 3, 8, 9, 10]),
             "iterations": np.array([10.0, 30, 70, 270, 330, 340]),
             "pc_builds": np.ones(6),
             "elapsed_s": np.array([1.0, 3, 7, 27, 33, 34]),
             "broken": np.array([1.0, 2, 4, 10, 11, 11])}
    (_, before), (_, after) = work_split.stage_rows(curve, 2e-4)
    f = work_split.floor(curve, after)
    assert (f["rupture_steps"], f["one_solve_steps"]) == (3, 2)
    assert f["closing_iterations"] == 50
    assert f["seconds_per_iteration"] == pytest.approx(0.1)
    assert f["floor_iterations"] == 150 and f["floor_seconds"] == pytest.approx(15)
    assert f["iterations"] == 310
    # Up to the peak: both steps broke one batch with one solve (10, 20 its).
    g = work_split.floor(curve, before)
    assert (g["rupture_steps"], g["closing_iterations"], g["floor_iterations"]) == (2, 15, 30)
    # Without a step of one batch and one solve there is no estimate.
    curve["cycles"][2] = curve["cycles"][4] = 2
    assert work_split.floor(curve, after) is None


def test_near_threshold_counts_post_peak_batches_that_hold_a_close_rupture():
    from lem_tools import work_split
    # Three batches after the peak strain 2e-4: (3, 0) has ratios 1.2 and
    # 1.02, (3, 1) has 1.5, (4, 0) a bare contact (threshold 0) and 1.04;
    # the rupture at the peak's strain is left out.
    broken = {"step": np.array([2.0, 3, 3, 3, 4, 4]), "cycle": np.array([0.0, 0, 0, 1, 0, 0]),
              "strain": np.array([2e-4, 3e-4, 3e-4, 3e-4, 4e-4, 4e-4]),
              "force": np.array([1.0, 1.2, 1.02, 1.5, 1e-3, 1.04]),
              "threshold": np.array([1.0, 1, 1, 1, 0, 1])}
    ruptures, batches, shares = work_split.near_threshold(broken, 2e-4, (0.01, 0.03, 0.05))
    assert (ruptures, batches) == (5, 3)
    assert shares[0.01] == (0.0, 0.0)
    assert shares[0.03] == pytest.approx((1 / 5, 1 / 3))
    assert shares[0.05] == pytest.approx((2 / 5, 2 / 3))


def test_margins_must_be_non_negative_numbers():
    from lem_tools import work_split
    from lem_tools.errors import ToolError
    assert work_split.margin_list("0.01,0.05") == (0.01, 0.05)
    for bad in ("x", "0.01,-1", "nan"):
        with pytest.raises(ToolError, match="--margins"):
            work_split.margin_list(bad)
