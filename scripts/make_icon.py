"""Draw the PLC Bridge brand icon: a rack of PLC modules under a suspension-bridge arc.

Usage: .venv/bin/python scripts/make_icon.py
Writes custom_components/plc_bridge/brand/icon.png (256 x 256) and icon@2x.png (512 x 512).
Drawn at 4x the larger size and scaled down, so every edge is anti-aliased.
"""

from __future__ import annotations

from pathlib import Path

from PIL import Image, ImageDraw

ROOT = Path(__file__).resolve().parent.parent
BRAND = ROOT / "custom_components" / "plc_bridge" / "brand"
CANVAS = 2048  # drawing units; every coordinate below is on a 1024 grid times SCALE
SCALE = CANVAS / 1024

BLUE = (3, 169, 244, 255)  # Home Assistant's primary blue
SLATE = (55, 71, 79, 255)
SLATE_LIGHT = (96, 125, 139, 255)
RAIL = (120, 144, 156, 255)
PANEL = (236, 239, 241, 255)
GREEN = (76, 175, 80, 255)
AMBER = (255, 193, 7, 255)

MODULES = [(128, 344), (368, 520), (544, 696), (720, 896)]  # (left, right), the CPU first
MODULE_TOP, MODULE_BOTTOM = 430, 868
ARC_LEFT, ARC_RIGHT, ARC_BASE, ARC_TOP = 96, 928, 520, 120


def box(*coords: float) -> tuple[float, ...]:
    """Scale 1024-grid coordinates to the canvas."""
    return tuple(c * SCALE for c in coords)


def arc_y(x: float) -> float:
    """Height of the bridge arc (a parabola) at x on the 1024 grid."""
    middle = (ARC_LEFT + ARC_RIGHT) / 2
    half = (ARC_RIGHT - ARC_LEFT) / 2
    return ARC_TOP + (ARC_BASE - ARC_TOP) * ((x - middle) / half) ** 2


def draw_bridge(draw: ImageDraw.ImageDraw) -> None:
    """Draw the arc and its hangers down to the module tops."""
    for x in range(176, 860, 76):
        draw.line(box(x, arc_y(x), x, MODULE_TOP), fill=BLUE, width=round(14 * SCALE))
    steps = 96
    points = [
        box(x, arc_y(x))
        for x in (ARC_LEFT + (ARC_RIGHT - ARC_LEFT) * i / steps for i in range(steps + 1))
    ]
    draw.line(points, fill=BLUE, width=round(56 * SCALE), joint="curve")
    for x in (ARC_LEFT, ARC_RIGHT):
        radius = 28
        draw.ellipse(box(x - radius, ARC_BASE - radius, x + radius, ARC_BASE + radius), fill=BLUE)


def draw_module(draw: ImageDraw.ImageDraw, left: float, right: float, cpu: bool) -> None:
    """Draw one module: housing, front panel, status LEDs and a row of terminals."""
    draw.rounded_rectangle(
        box(left, MODULE_TOP, right, MODULE_BOTTOM), radius=28 * SCALE, fill=SLATE
    )
    inset = 22
    draw.rounded_rectangle(
        box(left + inset, MODULE_TOP + 96, right - inset, MODULE_BOTTOM - 110),
        radius=14 * SCALE,
        fill=SLATE_LIGHT,
    )
    leds = [GREEN, AMBER] if cpu else [GREEN]
    for index, colour in enumerate(leds):
        cx, cy, r = left + 52 + index * 56, MODULE_TOP + 50, 18
        draw.ellipse(box(cx - r, cy - r, cx + r, cy + r), fill=colour)
    if cpu:
        port = (left + 60, MODULE_TOP + 150, right - 60, MODULE_TOP + 250)
        draw.rounded_rectangle(box(*port), radius=10 * SCALE, fill=PANEL)
        draw.rectangle(box(port[0] + 40, port[3] - 30, port[2] - 40, port[3]), fill=SLATE)
    count = 3
    pitch = (right - left - 2 * inset) / count
    for index in range(count):
        x = left + inset + index * pitch + pitch / 2
        draw.rounded_rectangle(
            box(x - 14, MODULE_BOTTOM - 84, x + 14, MODULE_BOTTOM - 36),
            radius=6 * SCALE,
            fill=PANEL,
        )


def draw_icon() -> Image.Image:
    """Return the icon on a transparent canvas."""
    image = Image.new("RGBA", (CANVAS, CANVAS), (0, 0, 0, 0))
    draw = ImageDraw.Draw(image)
    draw_bridge(draw)
    draw.rounded_rectangle(box(88, 842, 936, 900), radius=12 * SCALE, fill=RAIL)
    for index, (left, right) in enumerate(MODULES):
        draw_module(draw, left, right, cpu=index == 0)
    return image


def main() -> None:
    """Write both sizes of the icon."""
    BRAND.mkdir(parents=True, exist_ok=True)
    image = draw_icon()
    for name, size in (("icon.png", 256), ("icon@2x.png", 512)):
        image.resize((size, size), Image.Resampling.LANCZOS).save(BRAND / name, optimize=True)
        print(f"wrote {(BRAND / name).relative_to(ROOT)} ({size}x{size})")


if __name__ == "__main__":
    main()
