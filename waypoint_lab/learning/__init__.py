"""
The lab's task as Gymnasium environments on stdr_lite's world (no ROS): importing registers them.

    import gymnasium as gym
    import waypoint_lab.learning
    env = gym.make('waypoint_lab/Waypoints-v0', render_mode='rgb_array')

waypoint_lab/Waypoints-v0 is the lab's task for one robot (waypoints_env.py);
waypoint_lab.learning.WaypointsVectorEnv drives many robots in one world at once, as Gymnasium's
vector API defines (vector_env.py), also made by gym.make_vec('waypoint_lab/Waypoints-v0',
num_envs=100, vectorization_mode='vector_entry_point'), and as Stable-Baselines3's VecEnv
(sb3_vec_env.py); WaypointsParallelEnv puts robots that meet in one world, each an agent of
PettingZoo's Parallel API (parallel_env.py); policy_controller drives a robot of a live
stdr_lite node with any policy, through ROS (policy_controller.py).
"""

import gymnasium as gym

MAX_EPISODE_STEPS = 2000

gym.register(id='waypoint_lab/Waypoints-v0',
             entry_point='waypoint_lab.learning.waypoints_env:WaypointsEnv',
             vector_entry_point='waypoint_lab.learning.vector_env:WaypointsVectorEnv',
             max_episode_steps=MAX_EPISODE_STEPS)
