"""Image pairs by predicted footprint: only images of the same place, at most k each."""

from __future__ import annotations

import numpy as np

from designer.survey.pairs import footprint_pairs


def squares(centres, size=10.0):
    h = size / 2
    return [np.array([[x - h, y - h], [x + h, y - h], [x + h, y + h], [x - h, y + h]])
            for x, y in centres]


def test_images_of_different_places_are_never_paired():
    # two blocks of images 1 km apart (a repeating texture would match them)
    centres = [(x, y) for x in (0, 4, 8) for y in (0, 4)]
    centres += [(1000 + x, y) for x, y in centres]
    names = [f"I{k:02d}" for k in range(len(centres))]
    pairs = footprint_pairs(names, squares(centres))
    assert pairs
    for a, b in pairs:
        assert (int(a[1:]) < 6) == (int(b[1:]) < 6)


def test_each_image_keeps_its_k_most_overlapping_partners():
    """A long strip: every image overlaps the next 9 on each side; with k = 3 an image is
    paired with its 3 nearest on each side at most (6 partners), always its neighbours."""
    centres = [(float(x), 0.0) for x in range(40)]
    names = [f"I{k:02d}" for k in range(40)]
    pairs = footprint_pairs(names, squares(centres), k=3)
    partners = {n: set() for n in names}
    for a, b in pairs:
        partners[a].add(b)
        partners[b].add(a)
    assert max(len(p) for p in partners.values()) <= 6
    for k in range(39):
        assert names[k + 1] in partners[names[k]]
    assert all(abs(int(a[1:]) - int(b[1:])) <= 3 for a, b in pairs)
    assert len(footprint_pairs(names, squares(centres), k=100)) == sum(
        min(9, 39 - k) for k in range(40))


def test_a_small_overlap_is_not_a_pair():
    pairs = footprint_pairs(["a", "b"], squares([(0, 0), (9.8, 0)]), min_overlap=0.05)
    assert pairs == []
    assert footprint_pairs(["a", "b"], squares([(0, 0), (9.0, 0)]), min_overlap=0.05) == \
        [("a", "b")]
