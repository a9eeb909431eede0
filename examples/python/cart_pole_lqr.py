#!/usr/bin/env python3
"""Cart-pole balanced by LQR: the plant is a LeafSystem written in Python, the controller ROME's C++ LqrController.

The plant is linearized about the upright equilibrium (rome.linearize, central differences through the Python
derivatives), the LQR gain comes from the CARE, and the closed loop runs from a tilted start.
Exit status: 0 balanced (the state is within --tolerance of upright at the end), 3 not balanced, 1 bad input.

usage: PYTHONPATH=build/python /usr/bin/python3 examples/python/cart_pole_lqr.py [--tilt RAD] [--time S] [--plot FILE.png]
"""
import argparse
import math
import sys

import numpy as np

import rome


class CartPole(rome.LeafSystem):
    """State [x (m), theta (rad, 0 hanging down, pi upright), x' (m/s), theta' (rad/s)], input f (N) on the cart.

    Point mass m_p at the end of a massless pole of length l on a cart of mass m_c (Tedrake, Underactuated Robotics,
    Ch. 3): (m_c + m_p) x'' + m_p l (theta'' cos - theta'^2 sin) = f,  m_p l x'' cos + m_p l^2 theta'' + m_p g l sin = 0.
    """

    def __init__(self, x0, m_c=1.0, m_p=0.3, l=0.5, g=9.81):
        super().__init__("cart_pole")
        self.m_c, self.m_p, self.l, self.g = m_c, m_p, l, g
        self.declare_continuous_state(x0)
        self.declare_input_port("f", 1)
        self.declare_output_port("state", ["x", "theta", "xdot", "thetadot"], lambda c: c.continuous_state, feedthrough=False)

    def do_calc_time_derivatives(self, context):
        _, theta, xdot, thetadot = context.continuous_state
        f = self.eval_input(context, "f")[0]
        s, c = math.sin(theta), math.cos(theta)
        d = self.m_c + self.m_p * s * s
        xddot = (f + self.m_p * s * (self.l * thetadot ** 2 + self.g * c)) / d
        thetaddot = (-f * c - self.m_p * self.l * thetadot ** 2 * c * s - (self.m_c + self.m_p) * self.g * s) / (self.l * d)
        return [xdot, thetadot, xddot, thetaddot]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tilt", type=float, default=0.3, help="[rad] initial pole angle from upright (|tilt| < 1)")
    parser.add_argument("--time", type=float, default=10.0, help="[s] simulated time (0, 60]")
    parser.add_argument("--tolerance", type=float, default=1e-3, help="[-] largest |state - upright| at the end")
    parser.add_argument("--plot", default="", help="PNG file of the pole angle and the cart position (matplotlib)")
    args = parser.parse_args()
    if not abs(args.tilt) < 1.0 or not 0 < args.time <= 60 or not args.tolerance > 0:
        print(f"cart_pole_lqr: --tilt {args.tilt} must be in (-1, 1) rad, --time {args.time} in (0, 60] s, --tolerance positive",
              file=sys.stderr)
        return 1
    upright = np.array([0.0, math.pi, 0.0, 0.0])

    # Linearize the Python plant about the upright equilibrium (f = 0) and design the LQR on it.
    plant = CartPole(upright)
    context = plant.create_default_context()
    plant.fix_input_port(context, "f", [0.0])
    linearization = rome.linearize(plant, context, "f")

    builder = rome.DiagramBuilder()
    builder.add_system(CartPole(upright + np.array([0.0, args.tilt, 0.0, 0.0])))
    controller = builder.add_system(rome.LqrController("lqr", linearization, np.diag([10.0, 10.0, 1.0, 1.0]), np.eye(1)))
    builder.connect("cart_pole", "state", "lqr", "x")
    builder.connect("lqr", "u", "cart_pole", "f")
    logger = rome.add_vector_logger(builder, "logger", [("cart_pole", "state"), ("lqr", "u")], 0.01)
    diagram = builder.build("cart_pole_lqr")
    sim = rome.Simulator(diagram)
    status = sim.advance_to(args.time)
    final = diagram.get_continuous_state(sim.context)
    error = float(np.max(np.abs(final - upright)))
    print(f"LQR gain K = {np.array2string(controller.K, precision=3)}")
    print(f"closed-loop eigenvalues of A - B K: {np.array2string(np.linalg.eigvals(linearization.A - linearization.B @ controller.K), precision=3)}")
    print(f"after {args.time} s ({status.kind}): state {np.array2string(final, precision=6)}, largest |error| {error:.2e}")

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        data = logger.data(diagram.get_subsystem_context(logger, sim.context))
        figure, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
        axes[0].plot(data["time"], data["cart_pole.state.theta"] - math.pi, label="theta - pi [rad]")
        axes[0].plot(data["time"], data["cart_pole.state.x"], label="x [m]")
        axes[0].legend()
        axes[1].plot(data["time"], data["lqr.u[0]"], label="f [N]")
        axes[1].set_xlabel("time [s]")
        axes[1].legend()
        figure.savefig(args.plot, dpi=100)
        print(f"plot: {args.plot}")
    return 0 if status.kind == "limit" and error < args.tolerance else 3


if __name__ == "__main__":
    sys.exit(main())
