"""`vslsp vsl calibrate`: calibration.json from pictures of a checkerboard on the table, or from
four marked table points, checked against the known camera the pictures were taken through
(OpenCV's camera model with lens distortion, blur, noise and JPEG); and the pinhole camera with
distortion and the homography of vslsp.vsl.calibration answering within tolerance."""

import json

import numpy as np
import pytest
from helpers.cli import vslsp

from vslsp.experiments.photo_camera import Look, UserCamera, checkerboard
from vslsp.vision.image import write_image
from vslsp.vsl.calibration import calibration_from_dict

SIZE = (800, 600)
PATTERN = (9, 6)
SQUARE = 0.03  # m
DISTORTION = (-0.12, 0.03, 0.0, 0.0, 0.0)
BOARD = checkerboard(PATTERN, SQUARE, 4000.0)
CENTRE = (4 * SQUARE, -2.5 * SQUARE)


def saved(path, image):
    write_image(path, image)
    return path


def camera(tilt: float, heading: float) -> UserCamera:
    return UserCamera.looking_at(CENTRE, 0.55, tilt, heading, 900.0, SIZE, DISTORTION, (6.0, -4.0))


def table_distances(calibration, pixels):
    """The table distances (m) between consecutive pixels, through a calibration."""
    points = np.array([calibration.camera.pixel_to_table(*calibration.undistort_point(u, v)) for u, v in pixels])
    return np.linalg.norm(np.diff(points, axis=0), axis=1)


def true_points(cam: UserCamera, pixels):
    from vslsp.vsl.calibration import PinholeTable

    truth = calibration_from_dict(cam.calibration(), SIZE)
    assert isinstance(truth.camera, PinholeTable)
    return np.array([truth.camera.pixel_to_table(*truth.undistort_point(u, v)) for u, v in pixels])


@pytest.fixture(scope="module")
def board_pictures(tmp_path_factory):
    folder = tmp_path_factory.mktemp("board")
    rng = np.random.default_rng(0)
    views = [(12, 0), (18, 60), (15, 150), (20, 230), (10, 300), (16, 20)]
    files = []
    for n, (tilt, heading) in enumerate(views):
        picture = camera(tilt, heading).photograph(BOARD, Look(defocus_px=0.6, motion_px=0.0, noise=2.0), rng)
        files.append(saved(folder / f"board-{n}.png", picture))
    return files, camera(*views[-1])


def test_a_checkerboard_calibration_recovers_the_camera_and_the_table(board_pictures, tmp_path, capsys):
    files, last = board_pictures
    out = tmp_path / "calibration.json"
    size = f"{PATTERN[0]}x{PATTERN[1]}"
    code, stdout, err = vslsp(
        capsys, "vsl", "calibrate", *files, "--checkerboard", size, "--square", 30, "--out", out, "--json"
    )
    assert code == 0, err
    data = json.loads(out.read_text())
    assert json.loads(stdout)["rms_px"] == data["rms_px"] < 0.3
    assert np.allclose(data["camera_matrix"], last.matrix, atol=4.0)
    assert data["distortion"][0] == pytest.approx(DISTORTION[0], abs=0.02)
    found = calibration_from_dict(data, SIZE)
    truth = calibration_from_dict(last.calibration(), SIZE)
    grid = [(u, v) for u in range(100, 701, 100) for v in range(100, 501, 100)]  # where the boards were seen
    undone = np.array([found.undistort_point(u, v) for u, v in grid])
    assert np.abs(undone - [truth.undistort_point(u, v) for u, v in grid]).max() < 1.5
    # the table plane: the camera's eye as high over it, and every pixel seeing its true point
    eye = -found.camera.rotation.T @ found.camera.translation
    assert eye[2] == pytest.approx((-last.rotation.T @ last.translation)[2], abs=0.002)
    pixels = [(120, 100), (700, 110), (680, 520), (90, 500), (400, 300)]
    truth = true_points(last, pixels)
    assert np.allclose(table_distances(found, pixels), np.linalg.norm(np.diff(truth, axis=0), axis=1), atol=0.0015)


def test_one_picture_fits_the_focal_length_and_the_plane(board_pictures, tmp_path, capsys):
    files, _ = board_pictures
    cam = UserCamera.looking_at(CENTRE, 0.55, 14.0, 40.0, 900.0, SIZE)  # a lens without distortion
    picture = cam.photograph(BOARD, Look(motion_px=0.0), np.random.default_rng(1))
    image = saved(tmp_path / "board.jpg", picture)
    out = tmp_path / "calibration.json"
    code, _, err = vslsp(capsys, "vsl", "calibrate", image, "--checkerboard", "9x6", "--square", 30, "--out", out)
    assert code == 0, err
    data = json.loads(out.read_text())
    assert data["camera_matrix"][0][0] == pytest.approx(900.0, rel=0.02)
    pixels = [(150, 120), (650, 140), (640, 480), (160, 470)]
    truth = true_points(cam, pixels)
    assert np.allclose(
        table_distances(calibration_from_dict(data, SIZE), pixels),
        np.linalg.norm(np.diff(truth, axis=0), axis=1),
        atol=0.002,
    )


def test_four_marked_points_give_the_homography(tmp_path, capsys):
    cam = UserCamera.looking_at((0.4, 0.0), 0.8, 15.0, 10.0, 900.0, SIZE)
    image = saved(tmp_path / "table.png", cam.photograph(BOARD, Look(), np.random.default_rng(2)))
    table = np.array([[0.25, -0.2], [0.55, -0.22], [0.56, 0.21], [0.24, 0.19]])
    pixels = cam.project(np.hstack([table, np.zeros((4, 1))]))
    pairs = [f"{u:.2f},{v:.2f}:{x},{y}" for (u, v), (x, y) in zip(pixels, table)]
    out = tmp_path / "calibration.json"
    code, _, err = vslsp(capsys, "vsl", "calibrate", image, "--points", *pairs, "--out", out)
    assert code == 0, err
    found = calibration_from_dict(json.loads(out.read_text()), SIZE)
    for x, y in [(0.3, 0.0), (0.5, 0.1), (0.4, -0.15)]:
        u, v = cam.project(np.array([[x, y, 0.0]]))[0]
        assert np.allclose(found.camera.pixel_to_table(u, v), (x, y), atol=0.0005)
        assert np.allclose(found.image_pixel(x, y), (u, v), atol=0.05)


def test_the_pinhole_camera_undoes_its_lens_distortion():
    cam = camera(15.0, 30.0)
    calibration = calibration_from_dict(cam.calibration(), SIZE)
    points = np.array([[0.0, 0.0, 0.0], [0.2, -0.1, 0.0], [0.1, 0.05, 0.03]])
    for point, (u, v) in zip(points, cam.project(points)):
        assert np.allclose(calibration.image_pixel(*point), (u, v), atol=0.01)
        x, y = calibration.camera.pixel_to_table(*calibration.undistort_point(u, v), point[2])
        assert np.allclose((x, y), point[:2], atol=1e-4)


@pytest.mark.parametrize(
    "args, says",
    [
        (["--checkerboard", "9by6", "--square", "30"], "COLSxROWS"),
        (["--checkerboard", "9x6"], "--square"),
        (["--points", "1,2:0.1,0.2"], "at least four"),
        (["--points", "1,2:a,b"], "u,v:x,y"),
        ([], "either --checkerboard"),
    ],
)
def test_bad_calibration_input_exits_2_with_one_line(board_pictures, tmp_path, capsys, args, says):
    code, _, err = vslsp(capsys, "vsl", "calibrate", board_pictures[0][0], *args, "--out", tmp_path / "c.json")
    assert code == 2 and says in err and len(err.strip().splitlines()) == 1


def test_a_picture_without_the_board_is_named(tmp_path, capsys):
    blank = saved(tmp_path / "blank.png", np.full((600, 800, 3), 128, np.uint8))
    code, _, err = vslsp(
        capsys, "vsl", "calibrate", blank, "--checkerboard", "9x6", "--square", 30, "--out", tmp_path / "c.json"
    )
    assert code == 2 and "blank.png" in err and "no checkerboard" in err
