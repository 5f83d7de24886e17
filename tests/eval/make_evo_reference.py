#!/usr/bin/env python3
"""Writes evo_reference.json: evo's own APE/RPE figures on the shared trajectories.

Run with evo importable (pip install evo, or the minimal reconstruction described in the JSON's
"note") and numpy/scipy:
    python3 make_evo_reference.py ../../../shared/datasets/trajectories_evo > evo_reference.json
It calls what evo_ape / evo_rpe call: file_interface readers, sync.associate_trajectories (TUM
and EuRoC; KITTI is index-matched as `evo_ape kitti` does), PosePath3D.align (Umeyama; -a or -as),
metrics.APE / metrics.RPE with PoseRelation.translation_part and rotation_angle_deg, RPE delta in
frames with consecutive pairs, and PE.get_statistic for rmse, mean, median, std, min, max.
"""
import copy
import json
import sys

import numpy as np

import evo
from evo.core import metrics, sync
from evo.core.trajectory import PoseTrajectory3D
from evo.tools import file_interface

MAX_DIFF = 0.01
STATS = ["rmse", "mean", "median", "std", "min", "max"]

CASES = [
    # name, ground truth, estimate, reader, alignments, rpe delta (frames)
    ("fr1_xyz_rgbdslam", "freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt", "tum",
     ["none", "se3", "sim3"], 1),
    ("fr1_xyz_rgbdslam_delta10", "freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt",
     "tum", ["se3"], 10),
    ("fr1_xyz_orb_kf_mono", "freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-ORB_kf_mono.txt", "tum",
     ["se3", "sim3"], 1),
    ("fr2_desk_orb", "fr2_desk_groundtruth.txt", "fr2_desk_ORB.txt", "tum", ["se3", "sim3"], 1),
    ("v102", "V102_groundtruth.csv", "V102.txt", "euroc_tum", ["se3", "sim3"], 1),
    ("kitti_00_orb", "KITTI_00_gt.txt", "KITTI_00_ORB.txt", "kitti", ["none", "se3", "sim3"], 1),
]


def stats(metric):
    return {s: float(metric.get_statistic(metrics.StatisticsType(s))) for s in STATS}


def read(folder, name, reader):
    path = folder + "/" + name
    if reader == "kitti":
        return file_interface.read_kitti_poses_file(path)
    if name.endswith(".csv"):
        return file_interface.read_euroc_csv_trajectory(path)
    return file_interface.read_tum_trajectory_file(path)


def evaluate(traj_ref, traj_est, align, delta):
    traj_ref = copy.deepcopy(traj_ref)
    traj_est = copy.deepcopy(traj_est)
    scale = 1.0
    if align != "none":  # as main_ape.ape / main_rpe.rpe: align the estimate once, then both metrics
        _, _, scale = traj_est.align(traj_ref, correct_scale=(align == "sim3"),
                                     correct_only_scale=False)
    out = {"align": align, "scale": float(scale), "matched": int(traj_est.num_poses)}
    ape_t = metrics.APE(metrics.PoseRelation.translation_part)
    ape_t.process_data((traj_ref, traj_est))
    ape_r = metrics.APE(metrics.PoseRelation.rotation_angle_deg)
    ape_r.process_data((traj_ref, traj_est))
    # APE.E holds est - ref positions for translation_part: its per-axis rmse.
    axis_rmse = np.sqrt(np.mean(np.asarray(ape_t.E) ** 2, axis=0))
    out["ate"] = {"trans": stats(ape_t), "rot_deg": stats(ape_r),
                  "trans_axis_rmse": {"x": float(axis_rmse[0]), "y": float(axis_rmse[1]),
                                      "z": float(axis_rmse[2])}}
    rpe_t = metrics.RPE(metrics.PoseRelation.translation_part, delta, metrics.Unit.frames,
                        all_pairs=False)
    rpe_t.process_data((traj_ref, traj_est))
    rpe_r = metrics.RPE(metrics.PoseRelation.rotation_angle_deg, delta, metrics.Unit.frames,
                        all_pairs=False)
    rpe_r.process_data((traj_ref, traj_est))
    out["rpe"] = {"delta_frames": delta, "pairs": len(rpe_t.error), "trans": stats(rpe_t),
                  "rot_deg": stats(rpe_r)}
    return out


def main(folder):
    cases = []
    for name, gt, est, reader, alignments, delta in CASES:
        traj_ref = read(folder, gt, reader)
        traj_est = read(folder, est, reader)
        if isinstance(traj_ref, PoseTrajectory3D) and isinstance(traj_est, PoseTrajectory3D):
            traj_ref, traj_est = sync.associate_trajectories(traj_ref, traj_est, max_diff=MAX_DIFF)
        for align in alignments:
            result = evaluate(traj_ref, traj_est, align, delta)
            result.update({"name": name, "groundtruth": gt, "estimate": est,
                           "max_diff": MAX_DIFF})
            cases.append(result)
    json.dump({"evo_version": evo.__version__, "numpy_version": np.__version__,
               "cases": cases}, sys.stdout, indent=1)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main(sys.argv[1])
