"""ANFIS step-size heuristics of Jang pinned by hand-made error histories (mutation-testing follow-up)."""

import pytest

from learners.anfis import ANFISGrid


@pytest.mark.parametrize("history,factor", [
    ([5.0, 4.0, 3.0, 2.0, 1.0], 1.1),    # four consecutive decreases: x1.1
    ([1.0, 2.0, 1.0, 2.0, 1.0], 0.9),    # up-down, up-down: x0.9
    ([2.0, 1.0, 2.0, 1.0, 2.0], 0.9),    # down-up, down-up: x0.9
    ([1.0, 2.0, 3.0, 4.0, 5.0], 1.0),    # steady increase: unchanged
    ([4.0, 3.0, 2.0, 1.0], 1.0),         # fewer than five errors: unchanged
])
def test_jang_step_heuristics(history, factor):
    """step -> 1.1 step after 4 decreases of E, 0.9 step after two up-down alternations, else unchanged."""
    assert ANFISGrid._adapt_step(0.01, history) == pytest.approx(0.01 * factor, rel=1e-15)
