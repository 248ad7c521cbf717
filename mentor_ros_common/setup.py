"""ament_python packaging of mentor_ros_common (see ROS 2 demo_nodes_py)."""

from setuptools import find_packages, setup

package_name = "mentor_ros_common"

setup(
    name=package_name,
    version="0.1.0",
    packages=find_packages(exclude=["test"]),
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + package_name]),
        ("share/" + package_name, ["package.xml"]),
        # RViz2's view of one robot: its topics are relative, rviz2 runs in its namespace
        ("share/" + package_name + "/config", ["config/mentor.rviz"]),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="MENTOR maintainers",
    maintainer_email="mentor@example.org",
    description="MENTOR suite: what the sim and planner nodes share.",
    license="Apache-2.0",
)
