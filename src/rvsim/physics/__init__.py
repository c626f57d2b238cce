"""The physics shared by both engines: contact laws and machine elements (issue 31;
docs/architecture.md).

The dynamic engine (:mod:`rvsim.dynamics`) integrates these elements in time, the quasi-static
engine (:mod:`rvsim.quasistatic`) solves them for equilibrium; this package imports neither
engine.  A module whose name starts with ``_`` is compiled with numba into the kernels and is
covered by the numba cache guard (``rvsim._cache_guard``) by its name; nothing is compiled at
import of this package.

* ``_layout`` - slots of the constant vector P, coordinate indices, output channels.
* ``_status`` - the one table of status codes of both engines (code, status string, message).
* ``_contact_law`` - Palmgren line contact, its damping, the carried Newton starts.
* ``_bearings`` - conforming contact (Johnson), bushings in series, rolling-element sets.
* ``_friction`` - pin, mesh, bearing and lip-seal friction on top of the normal forces.
* ``_pin_compliance`` - the FE pin-in-groove compliance in series with its contact.
* ``_single_stage`` - input shaft, output pins and pin-ring frame of the single-stage drive.
* ``_fe_contacts`` - the pin contacts of a finite-element disc, solved together.
* ``_fe_modes`` - the modal coordinates of a finite-element disc.
* ``_fe_holes`` - the finite-element disc's crank holes as load points.
* ``_fe_crank`` - the arm bushings of a finite-element crank, solved together.
* ``_fe_carrier`` - the support bushings on the finite-element carrier and flange plates.
* ``_frames`` - the one kinematic pose: crank stations, shared cosines and sines, disc frames,
  eccentric directions, crank-hole stations.
* ``_gear_mesh`` - the two-flank sun-planet gear mesh.
* ``_pins`` - the pin contacts (pin loop, coupled FE pins, pin friction, ring as output) and
  what each pin carries to its next evaluation.
* ``_crank_bearings`` - arm and support bushings or rolling bearings, the FE crank's pair, their
  stiffness matrices, and the one call of them per force evaluation.
* ``_forces`` - ``forces_at`` / ``forces_with``: the one force evaluation of both engines.
* ``compliance`` - Palmgren coefficient and tooth, pin and ring compliances (plain Python).
* ``stiffening`` - one element's force laws made s times stiffer, for the compliance budget
  (plain Python).
* ``rating_life`` - ISO 281 rating life of rolling bearings (plain Python).
* ``losses`` - lubricant viscosity at a temperature (ASTM D341) and lip-seal drag
  (ISO/TR 14179-2) (plain Python).

The dynamic engine's step loop (``rvsim.dynamics._kernel``) calls ``_forces.forces_with`` at the
input motion and load of its run's schedule; the quasi-static solver calls ``_forces.forces_at``.
"""
