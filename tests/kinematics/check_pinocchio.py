"""Check mcm-kinematics against Pinocchio, a rigid-body library nobody here wrote.

    check_pinocchio.py URDF CASES

URDF: the robot description the ROS 2 node generates, with a fixed joint from `flange` to a
`tcp` link (the TCP transform). CASES: the JSON of `kinematics/examples/pinocchio_cases.rs`.
For every case, Pinocchio's TCP pose (`tcp` frame) and its frame Jacobian in
LOCAL_WORLD_ALIGNED (linear velocity of the frame's origin, then angular velocity, both in
world axes: mcm-kinematics' convention) at `q` must equal the crate's within 1e-9 (m, and
unitless entries of the rotation and the Jacobian); every IK solution must lie within the
URDF's joint limits and put Pinocchio's TCP at the case's pose within 1 um and 1e-6 rad.
Prints a summary; exits non-zero naming every case that disagrees.
"""

import json
import sys

import numpy as np
import pinocchio as pin

POSE_TOL = 1e-9
JACOBIAN_TOL = 1e-9
IK_POSITION_TOL = 1e-6
IK_ANGLE_TOL = 1e-6


def main(urdf_path, cases_path):
    model = pin.buildModelFromUrdf(urdf_path)
    data = model.createData()
    if not model.existFrame("tcp"):
        sys.exit("the URDF has no frame `tcp`")
    tcp = model.getFrameId("tcp")
    with open(cases_path) as f:
        cases = json.load(f)["cases"]
    if model.nq != 6:
        sys.exit(f"the URDF's model has {model.nq} joint values; the arm has 6")

    def tcp_pose(q):
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacements(model, data)
        return data.oMf[tcp]

    failures = []
    worst = {"pose": 0.0, "jacobian": 0.0, "ik_position": 0.0, "ik_angle": 0.0}
    solutions = 0
    for n, case in enumerate(cases):
        q = np.array(case["q"])
        m = tcp_pose(q)
        want_p = np.array(case["pose"]["position"])
        want_r = np.array(case["pose"]["rotation"])
        err = max(np.abs(m.translation - want_p).max(), np.abs(m.rotation - want_r).max())
        worst["pose"] = max(worst["pose"], err)
        if err > POSE_TOL:
            failures.append(f"case {n} q={q.tolist()}: TCP pose differs by {err:.3g}")
        j = pin.computeFrameJacobian(model, data, q, tcp, pin.LOCAL_WORLD_ALIGNED)
        err = np.abs(j - np.array(case["jacobian"])).max()
        worst["jacobian"] = max(worst["jacobian"], err)
        if err > JACOBIAN_TOL:
            failures.append(f"case {n} q={q.tolist()}: Jacobian differs by {err:.3g}")
        if not case["solutions"]:
            failures.append(f"case {n} q={q.tolist()}: no IK solution for a reachable pose")
        target = pin.SE3(want_r, want_p)
        for s in case["solutions"]:
            solutions += 1
            s = np.array(s)
            if (s < model.lowerPositionLimit).any() or (s > model.upperPositionLimit).any():
                failures.append(f"case {n}: IK solution {s.tolist()} outside the joint limits")
            m = tcp_pose(s)
            dp = np.linalg.norm(m.translation - target.translation)
            da = np.linalg.norm(pin.log3(m.rotation.T @ target.rotation))
            worst["ik_position"] = max(worst["ik_position"], dp)
            worst["ik_angle"] = max(worst["ik_angle"], da)
            if dp > IK_POSITION_TOL or da > IK_ANGLE_TOL:
                failures.append(
                    f"case {n}: IK solution {s.tolist()} puts the TCP {dp:.3g} m and "
                    f"{da:.3g} rad from the pose"
                )
    print(
        f"checked {len(cases)} configurations and {solutions} IK solutions against Pinocchio "
        f"{pin.__version__}; largest differences: TCP pose {worst['pose']:.3g}, Jacobian "
        f"{worst['jacobian']:.3g}, IK {worst['ik_position']:.3g} m / {worst['ik_angle']:.3g} rad"
    )
    if failures:
        print(f"{len(failures)} disagreements:", file=sys.stderr)
        for f in failures[:50]:
            print("  " + f, file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
