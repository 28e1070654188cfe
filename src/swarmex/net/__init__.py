"""The missions as networked programs over ZeroMQ, driving the simulators' own policy objects.

* :mod:`~swarmex.net.wire` — frames (msgpack + CRC32) and the decoders every receiver uses;
* :mod:`~swarmex.net.traversal`, :mod:`~swarmex.net.server`, :mod:`~swarmex.net.agent` —
  seed 000's server and UAV clients (``swarmex serve`` / ``swarmex agent``);
* :mod:`~swarmex.net.mesh` — seed 003's robots and display as processes on a mesh
  (``swarmex explore --processes``; its parts in ``mesh_*``: scenario, frames, node,
  robot, display, record);
* :mod:`~swarmex.net.routing` — the mesh's routing tables;
* :mod:`~swarmex.net.vehicle`, :mod:`~swarmex.net.mavlink`, :mod:`~swarmex.net.uav_emulator`
  — the vehicle an agent flies (simulated, or a MAVLink copter through the extra ``uav``)
  and a MAVLink copter emulator for tests (docs/uav.md);
* :mod:`~swarmex.net.events`, :mod:`~swarmex.net.watch` — the live monitor stream;
* :mod:`~swarmex.net.limits` — the bounds every networked command checks its options by.

docs/net.md says how and why.
"""
