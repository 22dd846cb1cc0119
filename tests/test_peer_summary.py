"""The peer benchmark's summary (benches/peer_taichi.py; Taichi itself is not needed)."""

import importlib.util
import math
from pathlib import Path

import pytest


def load_peer():
    path = Path(__file__).resolve().parents[1] / "benches" / "peer_taichi.py"
    spec = importlib.util.spec_from_file_location("peer_taichi", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_summary_gives_median_mean_with_its_error_and_best_against_best():
    peer = load_peer()
    ours = [12.0, 15.0, 9.0, 16.0]
    theirs = [8.0, 10.0, 9.0, 8.0]  # ratios 1.5, 1.5, 1.0, 2.0
    text = peer.summary(ours, theirs)
    mean = 1.5
    error = math.sqrt(((0.0 + 0.0 + 0.25 + 0.25) / 3)) / 2  # sample s.d. / √n
    assert "1.00–2.00" in text
    assert "median 1.50" in text
    assert f"mean {mean:.2f} ± {error:.2f}" in text  # ± 0.20
    assert "best against best 1.60" in text  # 16 / 10, not the best pair's ratio 2.00
    assert "pairs: 4" in text


def test_summary_of_one_pair_has_no_error():
    text = load_peer().summary([10.0], [8.0])
    assert "median 1.25" in text and "±" not in text and "pairs: 1" in text


def test_collected_instructions_reads_callgrinds_last_total():
    peer = load_peer()
    output = "==12== Events    : Ir\n==12== Collected : 5457664766\n==12==\n==12== I   refs: 5,457,664,766\n"
    assert peer.collected_instructions(output) == 5457664766
    assert peer.collected_instructions("==1== Collected : 1,234\n==2== Collected : 99\n") == 99
    with pytest.raises(ValueError, match="Collected"):
        peer.collected_instructions("no count here")


def test_per_particle_step_divides_the_difference_by_the_extra_particle_steps():
    peer = load_peer()
    # 1e6 instructions of start-up, then 450 per particle-step: 10 vs 60 steps of 1000 particles.
    short, long = 1_000_000 + 450 * 10 * 1000, 1_000_000 + 450 * 60 * 1000
    assert peer.per_particle_step(short, long, 50, 1000) == 450.0
    with pytest.raises(ValueError):
        peer.per_particle_step(short, long, 0, 1000)


def test_check_tells_round_off_from_a_different_step():
    peer = load_peer()
    scale = 2.0e4  # Pa, the largest stress
    # Round-off after 300 steps (measured 1.4e-17 m, 1.9e-15 of the stress) passes...
    assert peer.same_step(1.4e-17, 1.9e-15 * scale, scale)
    # ...a different boundary rule in the re-map (8.4e-8 m, 0.9 % after 50 steps) does not,
    assert not peer.same_step(8.4e-8, 9.2e-3 * scale, scale)
    # nor a stress difference alone, a position difference alone, or NaN.
    assert not peer.same_step(1e-17, 1e-6 * scale, scale)
    assert not peer.same_step(1e-9, 0.0, scale)
    assert not peer.same_step(math.nan, 0.0, scale)
    assert peer.same_step(peer.CHECK_POSITION_TOLERANCE, peer.CHECK_STRESS_TOLERANCE * scale, scale)


if __name__ == "__main__":
    pytest.main([__file__])
