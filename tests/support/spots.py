"""Shared material for the spot tests: a disc envelope, a blank canvas, deleting a placement."""

from texeditor.recipe.actions import NewCanvas, SetLevels
from texeditor.recipe.history import History
from texeditor.spots.actions import DeleteSpot, spot_ref
from texeditor.spots.envelope import Envelope


DISC = Envelope.ellipse(12, 12).dumps()


def canvas(width=48, height=32, levels=4, base=None) -> History:
    history = History()
    history.apply(NewCanvas(width, height, levels))
    if base is not None:
        history.apply(SetLevels(0, 0, height, width, base))
    return history


def delete(history, step, spot=None) -> DeleteSpot:
    action = DeleteSpot(step, spot_ref(history.actions[step]), spot)
    history.apply(action)
    return action

