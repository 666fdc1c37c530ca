"""plastic_section keeps its fit of a frozen law and wall: the same numbers as a fresh fit,
copies handed out, and a fresh fit for any other law, wall or option."""
import numpy as np

from rfesim.materials.section import PipeWall
from rfesim.materials.sde_plastic import _fit_section, _fit_section_memo, plastic_section
from rfesim.materials.stress_strain import Bilinear, RambergOsgood, TabulatedLaw

WALL = PipeWall(0.3239, 0.0159, 207e9)
RO = RambergOsgood(207e9, 450e6, 15.0)


def _same(a, b):
    for name in ("params", "break_curvatures", "break_moments", "stress_geometry"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert (a.history_width, a.bending_stiffness, a.yield_curvature, a.yield_moment, a.plastic_moment) == \
           (b.history_width, b.bending_stiffness, b.yield_curvature, b.yield_moment, b.plastic_moment)


def test_memo_is_the_fit_and_hands_out_copies():
    _fit_section_memo.cache_clear()
    first = plastic_section(RO, WALL)
    first.params[:] = -1.0                       # a caller spoiling its copy
    first.break_moments[:] = 0.0
    second = plastic_section(RO, WALL)
    info = _fit_section_memo.cache_info()
    assert (info.hits, info.misses) == (1, 1)
    _same(second, _fit_section(RO, WALL, 40, 100.0))
    assert second.params is not first.params


def test_other_law_wall_or_options_fit_again():
    _fit_section_memo.cache_clear()
    base = plastic_section(RO, WALL)
    others = [plastic_section(RambergOsgood(207e9, 450e6, 16.0), WALL),
              plastic_section(RO, PipeWall(0.3239, 0.0200, 207e9)),
              plastic_section(RO, WALL, segments=30),
              plastic_section(RO, WALL, max_curvature_ratio=50.0),
              plastic_section(Bilinear(207e9, 450e6, 0.01), WALL)]
    assert _fit_section_memo.cache_info().misses == 6
    for o in others:
        assert not np.array_equal(o.params, base.params) or o.params.shape != base.params.shape


def test_unhashable_table_still_fits():
    law = TabulatedLaw(207e9, [450e6 / 207e9, 0.01, 0.05], [450e6, 480e6, 520e6])   # lists: not hashable
    _fit_section_memo.cache_clear()
    sec = plastic_section(law, WALL)
    assert _fit_section_memo.cache_info().misses == 0
    _same(sec, _fit_section(law, WALL, 40, 100.0))
