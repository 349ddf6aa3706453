"""Vehicle simulations with fitted tyres.

Pham, Hamedmoghadam and Shorten (2025), *Vehicle dynamics control for
simultaneous optimization of tire emissions and performance in EVs* (arXiv
2504.10709): wear-aware axle torque allocation for an all-wheel-drive EV
with low-wear hard tyres in front and soft tyres at the rear; equation
numbers below are theirs.

* :mod:`~tyrefit.sim.vehicle` - bicycle model with wheel spin and drag in path
  coordinates (Eq. 1-13), :class:`~tyrefit.sim.vehicle.SimResult`;
* :mod:`~tyrefit.sim.tyres` - axle tyres at the static loads, the bundled tyres;
* :mod:`~tyrefit.sim.path` - roads in path coordinates, UK design radii;
* :mod:`~tyrefit.sim.emission` - particle emission vs force (Eq. 14);
* :mod:`~tyrefit.sim.traction` - stopping distance, treadwear-traction law,
  emission ratio k (Eq. 15-18, 41-43);
* :mod:`~tyrefit.sim.allocator` - base-force prediction, closed-form split,
  Alg. 1, slip limits, force-tracking torque controller (Eq. 19-34, 49-50);
* :mod:`~tyrefit.sim.driver` - comfort-limited human-like driver;
* :mod:`~tyrefit.sim.simulate` - the fixed-step closed loop;
* :mod:`~tyrefit.sim.scenarios` - braking, straight and curved scenarios;
* :mod:`~tyrefit.sim.plots` - the paper's panels.

:mod:`tyrefit.sim.adhesion` (the road-adhesion EKF of Zhang et al. 2024) lives here too but
is independent of these modules.
"""
