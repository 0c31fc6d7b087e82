# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""The sky of birdcage's sky tools (docs/sky.md): one implementation of time, targets, passes,
the mount model and the rotctld client, shared by birdcage-track and birdcage-align."""
