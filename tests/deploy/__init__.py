"""The image and the compose stack, built and run with podman (marker ``container``)."""
