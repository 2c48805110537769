"""
Gymnasium environments on stdr_lite's world (no ROS): importing this module registers them.

    import gymnasium as gym
    import stdr_lite.learning
    env = gym.make('stdr_lite/Waypoints-v0', render_mode='rgb_array')

stdr_lite/Waypoints-v0 is the lab's task for one robot (waypoints_env.py);
stdr_lite.learning.WaypointsVectorEnv drives many robots in one world at once, as Gymnasium's
vector API defines (vector_env.py), also made by gym.make_vec('stdr_lite/Waypoints-v0',
num_envs=100, vectorization_mode='vector_entry_point'); policy_controller drives a robot of a
live stdr_lite node with any policy, through ROS (policy_controller.py).
"""

import gymnasium as gym

MAX_EPISODE_STEPS = 1000

gym.register(id='stdr_lite/Waypoints-v0',
             entry_point='stdr_lite.learning.waypoints_env:WaypointsEnv',
             vector_entry_point='stdr_lite.learning.vector_env:WaypointsVectorEnv',
             max_episode_steps=MAX_EPISODE_STEPS)
