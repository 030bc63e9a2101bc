"""What a stopped render says it kept (``designer render`` on Ctrl-C, the Render panel
on Cancel): how to continue only while something is left to render (issue 53,
finding 6: a cancel after the last image said "start the render again to render only
the rest" when there was no rest)."""

from __future__ import annotations

from designer.render.pipeline import ImagesKept


def test_a_cancel_after_the_last_image_says_nothing_is_left():
    kept = ImagesKept(total=4, up_to_date=4, rendered_now=4, out_of_date=0, not_rendered=0)
    for resume in (True, False):
        text = kept.text(resume, resume_option="'resume' ticked", rerun="start the render")
        assert "rest" not in text and "start the render" not in text, text
        assert text == "all 4 images up to date (4 rendered by this run); nothing is left "\
            "to render", text


def test_a_cancel_with_images_left_says_how_to_render_the_rest():
    kept = ImagesKept(total=4, up_to_date=3, rendered_now=1, out_of_date=0, not_rendered=1)
    assert kept.text(True) == ("3 of 4 images up to date (1 rendered by this run); "
                               "1 not rendered; run the same command again to render "
                               "only the rest")
    stale = ImagesKept(total=4, up_to_date=3, rendered_now=3, out_of_date=1, not_rendered=0)
    assert stale.text(False).endswith("run the same command with --resume to render only "
                                      "the rest"), stale.text(False)
