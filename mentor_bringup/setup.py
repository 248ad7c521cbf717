"""ament_python packaging of mentor_bringup (see ROS 2 demo_nodes_py)."""

from setuptools import find_packages, setup

package_name = "mentor_bringup"

setup(
    name=package_name,
    version="0.1.0",
    packages=find_packages(exclude=["test"]),
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + package_name]),
        ("share/" + package_name, ["package.xml"]),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="MENTOR maintainers",
    maintainer_email="mentor@example.org",
    description="MENTOR suite: the simulator and its planners together (the demo).",
    license="Apache-2.0",
    entry_points={"console_scripts": ["demo = mentor_bringup.demo:main"]},
)
