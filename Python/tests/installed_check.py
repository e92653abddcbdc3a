"""The installed package loads the installed library and runs a scene.
Usage: installed_check.py PREFIX"""
import os
import sys

import numpy as np

import talus

prefix = os.path.realpath(sys.argv[1])
assert os.path.realpath(talus.__file__).startswith(prefix), talus.__file__
assert os.path.realpath(talus.library_path).startswith(prefix), talus.library_path
w = talus.World(gravity=(0, 0, -9.81))
w.add_species("g", 2500.0, 0.01)
w.add_law(talus.ContactLaw("linear", k_n=1e4))
w.add_wall(talus.Wall.plane())
w.add_particle((0, 0, 0.0099), radius=0.01)
w.timestep = 0.1 * w.critical_timestep()
w.setup()
w.x[0, 2] = 0.0095                      # through the view
w.compute_forces()
f = w.f[0, 2]
assert abs(f - (1e4 * 5e-4 - 9.81 * w.mass[0])) < 1e-12 * abs(f), f
w.step(10)
print(f"installed package {talus.__file__} with {talus.library_path}: f_z = {f:.6g} N, z = {w.x[0, 2]:.6g} m")
