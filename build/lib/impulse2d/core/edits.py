"""Compiled edits from outside the step (``impulse2d.edit`` calls them): waking a body's
island, switching a body on or off, forgetting its contacts, with the same code the
step uses."""

from __future__ import annotations

from ._jit import kernel
from .events import disable, enable, forget_contacts
from .sleep import wake_island, wake_neighbours


@kernel
def wake_bodies(body, body_i, layout, contact_i, world_i, worlds, slot, neighbours) -> None:
    shapes = layout[: body.shape[1]]
    for w in worlds:
        wake_island(body, body_i, shapes, w, slot)
        if neighbours:
            wake_neighbours(body, body_i, shapes, contact_i, world_i, w, slot)


@kernel
def switch_bodies(body, body_i, layout, contact, contact_i, world_i, worlds, on, slot) -> None:
    shapes = layout[: body.shape[1]]
    for k in range(worlds.size):
        if on[k]:
            enable(body, body_i, shapes, contact, contact_i, world_i, worlds[k], slot)
        else:
            disable(body, body_i, shapes, contact, contact_i, world_i, worlds[k], slot)


@kernel
def forget_body_contacts(contact, contact_i, world_i, slot) -> None:
    for w in range(world_i.shape[0]):
        forget_contacts(contact, contact_i, world_i, w, slot)
