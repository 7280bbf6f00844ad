"""Training the lidarscout heightmap network (run with /usr/bin/python3; Debian packages only).

Nothing here runs the `lidarscout` program or parses its output: it reads the files the program makes
(`lidarscout train-data`'s windows, train_data.py; `lidarscout eval --json`, loso.py), which the scripts
(scripts/train_model.sh, loso_eval.sh, train_gpu.sh) make with the program because the Python module
(`import lidarscout`) has neither: the training windows and their targets, and the evaluation of a network
against them, are the program's pipelines (src/pipelines), not the module's points and rasters."""
