"""See it move: 3-D animation (mp4, gif) and a self-contained interactive page of a run.

Layer above plotting and export; matplotlib and imageio are imported lazily, only
when a video is written.
"""

from celtstone.visual.animation import VideoInfo as VideoInfo
from celtstone.visual.animation import animate as animate
from celtstone.visual.animation import animate_comparison as animate_comparison
from celtstone.visual.frames import PAGE_FRAME_LIMIT as PAGE_FRAME_LIMIT
from celtstone.visual.frames import PLOT_BUCKETS as PLOT_BUCKETS
from celtstone.visual.frames import VIDEO_FPS_LIMITS as VIDEO_FPS_LIMITS
from celtstone.visual.frames import VIDEO_FRAME_LIMITS as VIDEO_FRAME_LIMITS
from celtstone.visual.runs import load_run as load_run
from celtstone.visual.viewer import PAGE_SIZE_LIMIT as PAGE_SIZE_LIMIT
from celtstone.visual.viewer import PageInfo as PageInfo
from celtstone.visual.viewer import write_viewer as write_viewer

__all__ = [
    "PAGE_FRAME_LIMIT",
    "PAGE_SIZE_LIMIT",
    "PLOT_BUCKETS",
    "VIDEO_FPS_LIMITS",
    "VIDEO_FRAME_LIMITS",
    "PageInfo",
    "VideoInfo",
    "animate",
    "animate_comparison",
    "load_run",
    "write_viewer",
]
