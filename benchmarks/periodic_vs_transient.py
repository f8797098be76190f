"""Steps and solver time of the periodic orbit (time.method = "periodic") against the
transient stepped until settled: the periodic rows of ``vibrofric bench``, alone.

    PYTHONPATH=. python benchmarks/periodic_vs_transient.py
"""

from vibrofric.bench import periodic_vs_transient

if __name__ == "__main__":
    print("\n".join(periodic_vs_transient.markdown(periodic_vs_transient.measure())))
