#!/usr/bin/python3
"""How honest LD's variance of the mean is: per scene, the mean over pixels and seeds of the
film's variance of the mean (`render --variance-out`, the sample variance over n) against the
mean squared error of the same renders against a high-spp reference.

Under independent sampling the ratio is 1. Under the low-discrepancy sampler the sample
variance ignores the stratification, so V over-states the error: a score that compares a
filter's error with V (SURE) then favours filtering. The reference's own error adds to the
measured error, so the printed ratio is a lower bound.

Usage: bench/ld_variance.py [--spp 16] [--seeds 8] [--size 128x128] [--ref-spp 2048]
                            [--scenes tire,cornell,balls] [--sampler ld|independent]
"""
import argparse
import array
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_pfm(path):
    with open(path, 'rb') as f:
        f.readline()
        f.readline()
        scale = float(f.readline())
        values = array.array('f')
        values.frombytes(f.read())
    if scale > 0:  # big-endian
        values.byteswap()
    return values


def render(binary, scene, spp, seed, size, out, sampler, variance=None):
    cmd = [binary, 'render', scene, '--method', 'ld', '--spp', str(spp), '--seed', str(seed),
           '--size', size, '-o', out, '-q']
    if sampler != 'ld':
        cmd += ['--sampler', sampler]
    if variance:
        cmd += ['--variance-out', variance]
    subprocess.run(cmd, check=True)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument('--spp', type=int, default=16)
    p.add_argument('--seeds', type=int, default=8)
    p.add_argument('--size', default='128x128')
    p.add_argument('--ref-spp', type=int, default=2048)
    p.add_argument('--scenes', default='tire,cornell,balls')
    p.add_argument('--sampler', default='ld', choices=['ld', 'independent'])
    p.add_argument('--bin', default=os.path.join(ROOT, 'build', 'penumbra'))
    a = p.parse_args()
    print(f'LD at {a.spp} spp, {a.size}, {a.seeds} seeds, sampler {a.sampler}; '
          f'reference {a.ref_spp} spp')
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.scenes.split(','):
            scene = os.path.join(ROOT, 'scenes', name + '.json')
            ref_path = os.path.join(tmp, 'ref.pfm')
            render(a.bin, scene, a.ref_spp, 1000, a.size, ref_path, 'ld')
            ref = read_pfm(ref_path)
            error = variance = 0.0
            for seed in range(1, a.seeds + 1):
                img_path, var_path = os.path.join(tmp, 'i.pfm'), os.path.join(tmp, 'v.pfm')
                render(a.bin, scene, a.spp, seed, a.size, img_path, a.sampler, var_path)
                img, var = read_pfm(img_path), read_pfm(var_path)
                error += sum((x - r) ** 2 for x, r in zip(img, ref))
                variance += sum(var)
            print(f'{name:10s} mean V / mean squared error = {variance / error:.2f}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
