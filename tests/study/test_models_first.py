"""A study's reconstructions are submitted with one run of each SfM model first, so the
workers find distinct models side by side (designer.study.run.models_first)."""

from designer.study.run import models_first


def test_the_first_run_of_each_model_goes_first_then_the_rest_in_order():
    # the example-processing design: calibration fixed (v000, v001) and radial (v002,
    # v003), each SfM model shared by its GCP modes and replicates
    infos = {f"v{v:03d}-r{r:02d}": {"sfm_group": "fixed" if v < 2 else "radial"}
             for v in range(4) for r in range(2)}
    order = models_first(list(infos), infos)
    assert order[:2] == ["v000-r00", "v002-r00"]
    assert sorted(order) == sorted(infos)
    # then the second run of each model, and so on, each model's runs in their order
    assert order[2:4] == ["v000-r01", "v002-r01"]
    assert [r for r in order if infos[r]["sfm_group"] == "fixed"] == \
        [r for r in infos if infos[r]["sfm_group"] == "fixed"]


def test_runs_without_a_shared_model_keep_their_order():
    infos = {"a": {}, "b": {"sfm_group": None}, "c": {}}
    assert models_first(list(infos), infos) == ["a", "b", "c"]
