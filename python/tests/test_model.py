"""Loading, values, errors with their locations, the solution and how it displays."""

import pickle

import pytest

import lagrange
from conftest import SEED_7_1

PENDULUM = """\
# A simple pendulum
coordinates theta
parameters m = 1, l = 2, g = 9.81
frame N
point P = l*sin(theta)*N.x - l*cos(theta)*N.y
particle P mass m
gravity -g*N.y
initial theta = 0.1
"""


def test_loads_a_file_and_text(seed_7_1):
    assert seed_7_1.coordinates == ["x", "theta"]
    assert seed_7_1.title.startswith("Exercise 7.1")
    pendulum = lagrange.Model.from_text(PENDULUM)
    assert pendulum.coordinates == ["theta"]
    assert pendulum.values["l"] == 2.0
    assert list(pendulum.initial_state()) == [0.1, 0.0]


def test_a_model_error_carries_the_located_diagnostic():
    text = PENDULUM.replace("particle P mass m", "particle P mass mm")
    with pytest.raises(lagrange.ModelError) as caught:
        lagrange.Model.from_text(text)
    error = caught.value
    assert (error.line, error.column) == (6, 17)
    assert error.kind == "input"
    message = str(error)
    assert "unknown name `mm`" in message
    assert "<text>:6:17" in message
    assert "particle P mass mm" in message  # the source line, drawn under
    assert isinstance(error, ValueError)


def test_a_file_error_names_the_file(tmp_path):
    path = tmp_path / "broken.lag"
    path.write_text("coordinates x\nparticle P mass 1\n")
    with pytest.raises(lagrange.ModelError) as caught:
        lagrange.Model.from_file(path)
    assert (caught.value.line, caught.value.column) == (2, 10)
    assert f"{path}:2:10" in str(caught.value)


def test_a_missing_file_is_an_input_error(tmp_path):
    with pytest.raises(lagrange.ModelError) as caught:
        lagrange.Model.from_file(tmp_path / "nowhere.lag")
    assert caught.value.line is None
    assert "cannot read the model file" in str(caught.value)


def test_with_values_sets_on_a_copy(seed_7_1):
    moon = seed_7_1.with_values(g=1.62, theta="pi/4", F="sin(t)")
    assert moon.values["g"] == 1.62
    assert moon.initial_state()[1] == pytest.approx(0.7853981633974483)
    assert seed_7_1.values["g"] == 9.81  # the original is unchanged
    with pytest.raises(lagrange.ModelError) as caught:
        seed_7_1.with_values(gg=1.0)
    assert "`gg` is not a parameter" in str(caught.value)
    with pytest.raises(TypeError):
        seed_7_1.with_values(g=[1.0])


def test_a_model_pickles_with_its_values(seed_7_1):
    moon = seed_7_1.with_values(g=1.62)
    copy = pickle.loads(pickle.dumps(moon))
    assert copy.values == moon.values
    assert copy.coordinates == moon.coordinates
    with pytest.raises(lagrange.ModelError) as caught:
        copy.with_values(gg=1.0)
    assert str(caught.value).startswith(str(SEED_7_1))  # errors still name the file


def test_solve_displays_the_course_solution(seed_7_1):
    solution = seed_7_1.solve()
    assert solution.title == seed_7_1.title
    titles = [s.title for s in solution.sections]
    for expected in ("The system", "Lagrangian function", "Lagrange equations (II type)",
                     "Equilibria and their stability", "Linearized dynamics"):
        assert expected in titles
    markdown = solution._repr_markdown_()
    assert markdown.startswith("# Exercise 7.1")
    assert "$$" in markdown and "\\begin{aligned}" in markdown
    latex = solution._repr_latex_()
    assert "\\documentclass" not in latex and "\\section*{The system}" in latex
    assert solution.latex.startswith("\\documentclass")
    assert "Generalized coordinates: x, θ." in str(solution)
    section = solution.section("Lagrangian function")
    assert section.markdown.startswith("## Lagrangian function")
    assert section._repr_markdown_() == section.markdown
    # The model's problem statement comes first (its `problem` statement), then the system.
    document_titles = [s["title"] for s in solution.document["sections"]]
    assert document_titles[0] == "Problem" and "The system" in document_titles


def test_the_solution_is_the_command_lines(seed_7_1, cli):
    import subprocess

    markdown = subprocess.run([cli, "solve", str(SEED_7_1), "--format", "md"],
                              check=True, capture_output=True, text=True).stdout
    assert seed_7_1.solve().markdown.strip() == markdown.strip()


def test_sympy_and_numpy_are_imported_only_when_asked():
    import subprocess
    import sys

    code = (
        "import sys, lagrange\n"
        "heavy = lambda: sorted(m for m in ('numpy', 'sympy', 'pandas') if m in sys.modules)\n"
        "print(heavy())\n"
        f"model = lagrange.Model.from_file({str(SEED_7_1)!r}); model.solve()\n"
        "print(heavy())\n"
        "model.equations_of_motion()\n"
        "print(heavy())\n"
    )
    lines = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                           text=True).stdout.split("\n")
    assert lines[:2] == ["[]", "[]"]
    assert "'sympy'" in lines[2]
