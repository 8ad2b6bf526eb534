#!/usr/bin/env python3
"""The weak- and strong-scaling model of docs/scaling.md: time per step of the distributed
solve on P ranks from the measured single-core cost per particle-update and the measured halo
volume, with a stated network latency and bandwidth. Prints the Markdown tables of the doc.

    bench/scaling_model.py [--t-particle S] [--bytes-per-node B] [--latency S] [--bandwidth B/S]

The defaults are this machine's measurements (docs/scaling.md, "Measured"): they are inputs,
not results of this script.
"""
import argparse
import math

p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("--t-particle", type=float, default=1.48e-7,
               help="s per particle-update on one core at large sizes (measured: 2M-particle slope, 1 rank)")
p.add_argument("--bytes-per-node", type=float, default=80.0,
               help="bytes sent per shared node and step, all exchanges together (mass, momentum, force and a "
                    "flag, 48 B; remapped momentum, 16 B; EVS sums, 16 B: 80 B without contact)")
p.add_argument("--latency", type=float, default=2e-6, help="s per message (InfiniBand-class network)")
p.add_argument("--bandwidth", type=float, default=10e9, help="bytes/s per rank (InfiniBand-class network)")
p.add_argument("--steps", type=float, default=1e5, help="steps of the run whose wall time is predicted (Oso: 1e5)")
p.add_argument("--particles-per-cell", type=float, default=4.0)
p.add_argument("--neighbours", type=float, default=6.0, help="ranks sharing nodes with a rank (2D partitions)")
p.add_argument("--exchanges", type=float, default=3.0, help="halo exchanges per step (P2G, remap, EVS)")
p.add_argument("--reductions", type=float, default=3.0, help="allreduce per step (time step, failure, signal)")
p.add_argument("--imbalance", type=float, default=1.10, help="largest particle imbalance before repartitioning")
args = p.parse_args()


def step_time(n_total, ranks):
    """(compute, communication, total) seconds per step on `ranks` ranks."""
    n = n_total / ranks
    compute = n * args.t_particle * (args.imbalance if ranks > 1 else 1.0)
    if ranks == 1:
        return compute, 0.0, compute
    # Shared nodes of a compact 2D part of n / ppc triangles: its perimeter, 4 sqrt(E / 2) nodes.
    shared = 4 * math.sqrt(n / args.particles_per_cell / 2)
    halo = args.exchanges * args.neighbours * args.latency + shared * args.bytes_per_node / args.bandwidth
    collectives = args.reductions * math.ceil(math.log2(ranks)) * args.latency
    migration = ranks * args.latency  # the all-to-all of the migration counts, pairwise
    comm = halo + collectives + migration
    return compute, comm, compute + comm


def row(n_total, ranks, baseline):
    compute, comm, total = step_time(n_total, ranks)
    return (f"| {n_total:.2e} | {ranks} | {n_total / ranks:.2e} | {compute * 1e3:.1f} ms | {comm * 1e6:.0f} us | "
            f"{100 * baseline / total:.1f} % | {total * args.steps / 3600:.1f} h |")


head = ("| particles | ranks | particles per rank | compute per step | communication per step | efficiency | "
        f"{args.steps:.0e} steps |\n|---:|---:|---:|---:|---:|---:|---:|")

print("Weak scaling: a fixed load per rank (the per-rank loads of 1e8 and 1e9 particles on 256 ranks);")
print("efficiency = time per step on 1 rank with that load / time per step on P ranks.\n")
print(head)
for per_rank in (1e8 / 256, 1e9 / 256):
    one = step_time(per_rank, 1)[2]
    for ranks in (1, 2, 16, 64, 256):
        print(row(per_rank * ranks, ranks, one))

print("\nThe runs asked about: 1e8 and 1e9 particles on 16 to 256 ranks;")
print("efficiency = time per step on 1 rank / (P x time per step on P ranks).\n")
print(head)
for n_total in (1e8, 1e9):
    serial = step_time(n_total, 1)[2]
    for ranks in (16, 32, 64, 128, 256):
        print(row(n_total, ranks, serial / ranks))

print("\nThe measured case, for comparison with docs/scaling.md (measured 87.0 %):\n")
print(head)
print(row(1.92e6, 2, step_time(1.92e6, 1)[2] / 2))
