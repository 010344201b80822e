"""Loading models, their parameters, and model errors."""
import pytest

import rfeid


def test_load_lists_parameters_sensors_and_sampling(knee_column):
    m = rfeid.Model.load(knee_column)
    names = [p.name for p in m.parameters]
    assert "a_n1" in names
    a = next(p for p in m.parameters if p.name == "a_n1")
    assert a.identified and a.min < a.value < a.max
    assert a.unit == "daN/um^2" and a.unit_scale == pytest.approx(1e13)
    assert m.sensors == ["knee_ax", "knee_ay", "knee_az"]
    assert m.sensor_units == ["m/s^2"] * 3
    assert m.sample_rate > 0 and m.duration > 0
    assert "knee-column" in repr(m)


def test_from_toml_equals_load(knee_column):
    text = knee_column.read_text()
    a = rfeid.Model.load(knee_column)
    b = rfeid.Model.from_toml(text, base_dir=knee_column.parent)
    assert a.parameters == b.parameters
    assert b.path is None


def test_a_bad_model_names_the_entry_and_field(tmp_path, knee_column):
    text = knee_column.read_text().replace('mass = "', 'mass = "-', 1)
    with pytest.raises(rfeid.ModelError) as e:
        rfeid.Model.from_toml(text, base_dir=knee_column.parent)
    assert "mass" in str(e.value)
    assert isinstance(e.value, ValueError)
    bad = tmp_path / "bad.toml"
    bad.write_text("[simulation]\nduration = 1\n")
    with pytest.raises(rfeid.ModelError) as e:
        rfeid.Model.load(bad)
    assert str(bad) in str(e.value)


def test_a_missing_file_is_a_model_error(tmp_path):
    with pytest.raises(rfeid.ModelError) as e:
        rfeid.Model.load(tmp_path / "none.toml")
    assert "none.toml" in str(e.value)


@pytest.mark.parametrize("text", ["", "[[body]]\nname = 3\n", "\x00", "gravity = [1, 2]\n" * 3, "[simulation\n"])
def test_no_text_crashes_the_interpreter(text):
    with pytest.raises(rfeid.ModelError):
        rfeid.Model.from_toml(text)


def test_exceptions_belong_to_the_package_and_pickle():
    import pickle

    for cls, base in [(rfeid.ModelError, ValueError), (rfeid.DataError, ValueError),
                      (rfeid.IdentificationError, RuntimeError)]:
        assert cls.__module__ == "rfeid" and issubclass(cls, base)
        e = pickle.loads(pickle.dumps(cls("m")))
        assert type(e) is cls and str(e) == "m"
