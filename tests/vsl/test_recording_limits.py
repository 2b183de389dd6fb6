"""The input bounds of the commands on a user's pictures (docs/recordings.md, "Limits"):
``vslsp vsl learn`` and ``vslsp learn-domain`` hold a folder's pictures in memory, so their
pixels together are bounded (``--max-pixels MP``), checked from each file's header before it is
decoded; ``vslsp vsl reproduce`` checks a scene's size from its header before decoding it. Each
refusal is exit 2, one line naming the file and saying what to do, before anything is written."""

import numpy as np
import pytest
from helpers.cli import refused, vslsp
from helpers.pictures import png_header

from vslsp.vision.image import write_image


def picture(seed: int) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 255, (480, 640, 3), dtype=np.uint8)


@pytest.fixture
def vsl_folder(tmp_path):
    folder = tmp_path / "recording"
    folder.mkdir()
    for k, role in enumerate(("pre", "mid", "post")):
        write_image(folder / f"01-{role}.png", picture(k))
    return folder


def test_vsl_learn_refuses_a_folder_over_max_pixels_naming_the_picture(vsl_folder, tmp_path, capsys):
    # 01-mid, 01-post, 01-pre are read in that order: 0.31 MP each, 0.92 MP with the third
    err = refused(capsys, "vsl", "learn", vsl_folder, "--out", tmp_path / "demo", "--max-pixels", "0.8")
    assert "01-pre.png" in err and "0.9 megapixels" in err and "--max-pixels MP" in err
    assert not (tmp_path / "demo").exists()  # before any work


def test_vsl_learn_checks_the_sum_from_a_header_before_decoding(vsl_folder, tmp_path, capsys):
    """01-post.png's header claims 640x480 but the file holds no pixel: it is refused for the sum
    its header gives (0.61 MP with 01-mid.png), before it is decoded."""
    (vsl_folder / "01-post.png").write_bytes(png_header(640, 480))
    err = refused(capsys, "vsl", "learn", vsl_folder, "--out", tmp_path / "demo", "--max-pixels", "0.5")
    assert "01-post.png" in err and "0.6 megapixels" in err


def test_vsl_learn_refuses_a_picture_whose_header_claims_too_many_pixels(vsl_folder, tmp_path, capsys):
    (vsl_folder / "01-post.png").write_bytes(png_header(100_000, 100_000))
    err = refused(capsys, "vsl", "learn", vsl_folder, "--out", tmp_path / "demo")
    assert "01-post.png" in err and "100000x100000" in err and "resize it" in err


@pytest.mark.parametrize("value", ["0", "-1", "nan", "20000"])
def test_max_pixels_must_be_a_positive_number_of_megapixels(vsl_folder, tmp_path, capsys, value):
    code, _, err = vslsp(capsys, "vsl", "learn", vsl_folder, "--out", tmp_path / "demo", "--max-pixels", value)
    assert code == 2 and "--max-pixels" in err


def test_learn_domain_refuses_pairs_over_max_pixels_naming_the_picture(tmp_path, capsys):
    folder = tmp_path / "pairs"
    (folder / "explore").mkdir(parents=True)
    for where in (folder, folder / "explore"):
        write_image(where / "01-pre.png", picture(0))
        write_image(where / "01-post.png", picture(1))
        (where / "names.json").write_text('{"01": "pull red"}')
    # read pre then post, the demonstration's then explore/'s: 0.31 MP each, 1.23 MP with the fourth
    err = refused(capsys, "learn-domain", folder, "--out", tmp_path / "out", "--max-pixels", "1")
    assert "explore/01-post.png" in err and "--max-pixels MP" in err
    assert not (tmp_path / "out").exists()


def test_learn_domain_refuses_an_explore_picture_of_another_size(tmp_path, capsys):
    folder = tmp_path / "pairs"
    (folder / "explore").mkdir(parents=True)
    write_image(folder / "01-pre.png", picture(0))
    write_image(folder / "01-post.png", picture(1))
    write_image(folder / "explore" / "01-pre.png", picture(2)[:240, :320])
    write_image(folder / "explore" / "01-post.png", picture(3))
    for where in (folder, folder / "explore"):
        (where / "names.json").write_text('{"01": "pull red"}')
    err = refused(capsys, "learn-domain", folder, "--out", tmp_path / "out")
    assert "explore/01-pre.png is 320x240 px" in err and "same camera" in err


def option_help(capsys, command: str, option: str) -> str:
    code, out, _ = vslsp(capsys, command, "--help")
    assert code == 0
    text = " ".join(out.split())
    start = text.index(option)
    return text[start : text.index(" --", start + len(option))]


@pytest.mark.parametrize("option", ["--robot-side", "--predicates"])
def test_learn_domain_takes_grounds_own_grounding_options(capsys, option):
    assert option_help(capsys, "learn-domain", option) == option_help(capsys, "ground", option)
