"""Steps and solver time of the periodic orbit (time.method = "periodic") against the
transient stepped until settled: the periodic rows of ``vibrofric bench``, alone.

    PYTHONPATH=. python benchmarks/periodic_vs_transient.py
"""

from vibrofric import periodic_bench

if __name__ == "__main__":
    print("\n".join(periodic_bench.markdown(periodic_bench.measure())))
