"""Library errors become talus.TalusError carrying the library's message."""
import pytest

import talus


def test_out_of_range_parameter():
    with pytest.raises(talus.TalusError) as err:
        talus.ContactLaw("linear", k_n=-1.0)
    e = err.value
    assert e.status == 1 and e.status_name == "invalid argument"
    assert "k_n = -1" in e.message and "outside" in e.message     # the value and the limit
    assert "at tl_contact_law.c:" in e.message                    # the trace the library keeps


def test_unknown_names_list_the_known_ones():
    with pytest.raises(talus.TalusError) as err:
        talus.ContactLaw("no_such_law")
    assert "no_such_law" in err.value.message and "hertz" in err.value.message
    with pytest.raises(talus.TalusError) as err:
        talus.Wall("plane", no_such_parameter=1.0)
    assert "no_such_parameter" in err.value.message and "normal_z" in err.value.message
    with pytest.raises(talus.TalusError) as err:
        talus.Stepper.__init__(object.__new__(talus.Stepper), _beam(), "newmark", no_such_option=1)
    assert "no_such_option" in err.value.message and "keep_factors" in err.value.message


def test_timestep_above_critical_names_both():
    w = talus.World()
    w.add_species("g", 2500.0, 0.01)
    w.add_law(talus.ContactLaw("linear", k_n=1e4))
    w.add_particle((0, 0, 0), radius=0.01)
    dtc = w.critical_timestep()
    w.timestep = 2 * dtc
    with pytest.raises(talus.TalusError) as err:
        w.setup()
    assert err.value.status_name == "unstable"
    assert f"time step {2 * dtc:g} s exceeds the critical time step {dtc:g} s" in err.value.message


def test_state_errors():
    w = talus.World()
    w.add_species("g", 2500.0, 0.01)
    w.add_particle((0, 0, 0), radius=0.01)
    with pytest.raises(talus.TalusError) as err:
        w.field("w")                                # no rotation yet
    assert err.value.status_name == "invalid state" and "enable_rotation" in err.value.message
    with pytest.raises(talus.TalusError) as err:
        w.field("colour")
    assert err.value.status_name == "not found" and "radius" in err.value.message
    law = talus.ContactLaw("linear", k_n=1.0)
    w.add_law(law)
    with pytest.raises(talus.TalusError):
        w.add_law(law)                              # owned by the world already


def _beam():
    mesh = talus.Mesh.box("hex8", (1, 2, 1), (0, 0, 0), (1, 2, 1))
    return talus.Solid(mesh, talus.Material("hooke", E=1e6, nu=0.3, density=1000.0), fix={"ymin": 7})


def test_stepper_options_are_the_types_parameters():
    import math
    newmark = {p["name"]: p for p in talus.parameters("stepper", "newmark")}
    assert newmark["beta"]["default"] == 0.25 and newmark["beta"]["hi"] == 0.5 and newmark["beta"]["unit"] == "1"
    assert newmark["max_iterations"]["default"] == 30 and newmark["atol"]["unit"] == "N"
    assert "blowup" not in newmark and "blowup" in [p["name"] for p in talus.parameters("stepper", "central_difference")]
    width = talus.parameters("cg_kernel", "lucy")[0]
    assert width["name"] == "width" and width["unit"] == "m" and math.isnan(width["default"])   # no default
    with pytest.raises(talus.TalusError) as err:
        talus.parameters("stepper", "no_such_stepper")
    assert "no_such_stepper" in err.value.message and "newmark" in err.value.message
    solid = _beam()
    with pytest.raises(talus.TalusError) as err:
        talus.Stepper(solid, "central_difference", beta=0.3)          # a setting the type does not read
    assert "'beta'" in err.value.message and "blowup" in err.value.message
    with pytest.raises(talus.TalusError) as err:
        talus.Stepper(solid, "newmark", beta=0.7)                      # outside the table's range
    assert "beta = 0.7 outside [0, 0.5]" in err.value.message
    with pytest.raises(talus.TalusError) as err:
        talus.Stepper(solid, "newmark", max_iterations=2.5)            # an integer field
    assert "max_iterations = 2.5 is not an integer" in err.value.message
    st = talus.Stepper(solid, "quasi_static", ramp_time=0.5, max_cuts=3)
    st.step(1.0)
    assert st.time == 1.0
