"""Makes the paper's released TorchScript networks (cg-tuwien/lidarscout: ipes_cnn.pt,
ipes_cnn_rgb.pt) run on a CPU-only LibTorch, for `lidarscout eval --methods released`.

    python3 -m lidarscout_train.released_cpu IN.pt OUT.pt

The published files were traced on CUDA: their serialized code creates one (empty) tensor with
device=torch.device("cuda:0"), which fails without a GPU. This rewrites that device to "cpu" in
the archive's code entries and copies every other entry (the weights) unchanged; it needs no
torch. The result stays the user's file: never commit it.
"""
import sys
import zipfile

CUDA = b'torch.device("cuda:0")'
CPU = b'torch.device("cpu")'


def convert(src, dst):
    """Copies the archive src to dst with CUDA device constants in code/*.py set to the CPU;
    returns how many were rewritten."""
    rewritten = 0
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w", zipfile.ZIP_STORED) as zout:
        for info in zin.infolist():
            data = zin.read(info.filename)
            if "/code/" in info.filename and info.filename.endswith(".py"):
                rewritten += data.count(CUDA)
                data = data.replace(CUDA, CPU)
            zout.writestr(info, data)
    return rewritten


def main(argv):
    if len(argv) != 2:
        sys.exit("usage: python3 -m lidarscout_train.released_cpu IN.pt OUT.pt")
    n = convert(argv[0], argv[1])
    print(f"{argv[1]}: {n} CUDA device constant(s) set to the CPU")


if __name__ == "__main__":
    main(sys.argv[1:])
