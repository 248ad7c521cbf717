"""ament_python packaging of mentor_planner_node (see ROS 2 demo_nodes_py)."""

from glob import glob

from setuptools import find_packages, setup

package_name = "mentor_planner_node"

setup(
    name=package_name,
    version="0.1.0",
    packages=find_packages(exclude=["test"]),
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + package_name]),
        ("share/" + package_name, ["package.xml"]),
        ("share/" + package_name + "/launch", ["launch/planner.launch.py"]),
        # robot presets, and the shipped planners: genome:=ugv-paper-dual-s1 from anywhere
        ("share/" + package_name + "/config", glob("config/*.yaml") + glob("config/*.rviz")),
        ("share/" + package_name + "/planners", sorted(glob("../planners/*.json"))),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="MENTOR maintainers",
    maintainer_email="mentor@example.org",
    description="MENTOR suite: the planner node.",
    license="Apache-2.0",
    entry_points={"console_scripts": ["planner = mentor_planner_node.planner:main"]},
)
