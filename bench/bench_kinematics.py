"""Arm kinematics beside Robotics Toolbox (roboticstoolbox-python), same problems.

Run: python bench/bench_kinematics.py [--configs 10000] [--samples 5000]

1. FK + Jacobian of a UR5 for N random configurations: trajkit in one batched call
   against Robotics Toolbox's compiled ETS ``fkine`` + ``jacob0`` called per
   configuration (its fastest path), and its DHRobot methods for reference.
2. IK along a Cartesian straight line of S samples, fixed orientation: trajkit's
   ``ik_path`` (a few knots solved in order, then every sample at once from
   interpolated seeds) and plain batched ``ik`` with every sample seeded from the
   start configuration, against Robotics Toolbox's compiled ``ik_LM`` per sample,
   warm-started from the previous sample's solution.

Both sides use the same UR5 DH table; medians over repetitions.
"""

from __future__ import annotations

import argparse

import numpy as np

from timing import median_seconds
from trajkit.kinematics import UR5

START = np.array([0.3, -1.2, 1.5, -1.9, -1.57, 0.2])  # a comfortable, non-singular pose
LINE = np.array([0.10, 0.15, -0.10])  # metres


def rtb_ur5():
    import roboticstoolbox as rtb

    chain = UR5()
    links = [
        rtb.RevoluteDH(d=d, a=a, alpha=alpha)
        for a, alpha, d in (
            (0.0, np.pi / 2, 0.089159),
            (-0.425, 0.0, 0.0),
            (-0.39225, 0.0, 0.0),
            (0.0, np.pi / 2, 0.10915),
            (0.0, -np.pi / 2, 0.09465),
            (0.0, 0.0, 0.0823),
        )
    ]
    robot = rtb.DHRobot(links, name="UR5")
    q = np.random.default_rng(1).uniform(-3, 3, 6)
    assert np.allclose(robot.fkine(q).A, chain.fk(q), atol=1e-12), "DH tables differ"
    return robot


def bench_fk(configs: int, repeats: int) -> None:
    chain, robot = UR5(), rtb_ur5()
    ets = robot.ets()
    q = np.random.default_rng(20261122).uniform(-np.pi, np.pi, (configs, 6))
    ours = median_seconds(lambda: chain.fk_and_jacobian(q), repeats) / configs
    sample = q[: min(configs, 2000)]

    def peer_ets() -> None:
        for row in sample:
            ets.fkine(row)
            ets.jacob0(row)

    def peer_dh() -> None:
        for row in sample[:200]:
            robot.fkine(row)
            robot.jacob0(row)

    theirs = median_seconds(peer_ets, repeats) / sample.shape[0]
    theirs_dh = median_seconds(peer_dh, max(3, repeats // 3)) / 200
    pose, jacobian = chain.fk_and_jacobian(sample[:50])
    worst = max(
        max(np.abs(ets.fkine(r).A - p).max(), np.abs(ets.jacob0(r) - j).max())
        for r, p, j in zip(sample[:50], pose, jacobian, strict=True)
    )
    print(f"FK + Jacobian, UR5, {configs} configurations (max difference {worst:.1e})")
    print(f"  trajkit batched          {ours * 1e6:9.3f} us/config")
    print(f"  rtb ETS per config       {theirs * 1e6:9.3f} us/config  ratio {theirs / ours:7.1f}x")
    print(
        f"  rtb DHRobot per config   {theirs_dh * 1e6:9.3f} us/config  "
        f"ratio {theirs_dh / ours:7.1f}x"
    )


def bench_ik(samples: int, repeats: int) -> None:
    chain, robot = UR5(), rtb_ur5()
    ets = robot.ets()
    start = chain.fk(START)
    poses = np.repeat(start[np.newaxis], samples, axis=0)
    poses[:, :3, 3] += np.linspace(0.0, 1.0, samples)[:, np.newaxis] * LINE
    solution = chain.ik_path(poses, START)
    batched = chain.ik(poses, q_seed=START, raise_on_failure=False)
    ours = median_seconds(lambda: chain.ik_path(poses, START), repeats) / samples
    cold = (
        median_seconds(lambda: chain.ik(poses, q_seed=START, raise_on_failure=False), repeats)
        / samples
    )

    def peer() -> tuple[np.ndarray, int]:
        q, ok = START.copy(), 0
        out = np.empty((samples, 6))
        for k in range(samples):
            result = ets.ik_LM(poses[k], q0=q, tol=1e-10)
            q = np.asarray(result.q)
            ok += int(result.success)
            out[k] = q
        return out, ok

    peer_q, peer_ok = peer()
    theirs = median_seconds(peer, max(3, repeats // 3)) / samples
    residual = np.abs(chain.fk(solution.q) - poses).max()
    batched_residual = np.abs(chain.fk(batched.q) - poses).max()
    peer_residual = np.abs(chain.fk(peer_q) - poses).max()
    print(f"IK along a {samples}-sample line, UR5, full pose")
    print(
        f"  trajkit ik_path          {ours * 1e6:9.3f} us/sample  success "
        f"{np.mean(solution.success):.3f}  max pose error {residual:.1e}"
    )
    print(
        f"  trajkit ik, one seed     {cold * 1e6:9.3f} us/sample  success "
        f"{np.mean(batched.success):.3f}  max pose error {batched_residual:.1e}  "
        f"(every sample seeded from the start)"
    )
    print(
        f"  rtb ik_LM warm-started   {theirs * 1e6:9.3f} us/sample  success "
        f"{peer_ok / samples:.3f}  max pose error {peer_residual:.1e}"
    )
    print(f"  ratio rtb / ik_path {theirs / ours:5.2f}x, rtb / ik one seed {theirs / cold:5.2f}x")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--configs", type=int, default=10_000)
    parser.add_argument("--samples", type=int, default=5_000)
    parser.add_argument("--repeats", type=int, default=9)
    args = parser.parse_args()
    bench_fk(args.configs, args.repeats)
    bench_ik(args.samples, args.repeats)


if __name__ == "__main__":
    main()
