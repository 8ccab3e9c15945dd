# The package needs nothing built: a plain setup.py lets `pip install ./python` work offline with
# Debian's pip and setuptools (a pyproject.toml would make pip fetch its build requirements).
from setuptools import setup

setup(
    name="cairn",
    version="0.1.0",
    description="Does the rest stay put? Stability of assemblies of rigid parts under part removal, "
    "by linear complementarity (Python interface to libcairn)",
    long_description=open("README.md", encoding="utf-8").read(),
    long_description_content_type="text/markdown",
    packages=["cairn"],
    python_requires=">=3.9",
    install_requires=["numpy"],
)
