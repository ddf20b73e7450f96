"""The scene loader's warnings (Scene.warnings: a value accepted that does
not act, a body no real one is) said from Python as the command line says
them, as SceneWarning, each override named as the caller gave it."""
import re
import warnings

_PLACE = re.compile(r"--set #(\d+) '")


class SceneWarning(UserWarning):
    """A scene accepted with a warning (docs/scene_keys.md): the message names the key and why."""


def warn_loaded(scene, texts, labels, said=0):
    """Each of scene.warnings as a SceneWarning, its "--set #k 'text'" named
    by labels[k - said - 1] as _relabelled names a refusal; a warning about
    one of the first `said` overrides (Scene.replace lays the scene's own
    values first: said when the scene was loaded) is not said again. Returns
    the scene."""
    for text in scene.warnings:
        m = _PLACE.match(text)
        if m:
            k = int(m.group(1)) - said
            if k < 1:
                continue
            if k <= len(labels):
                text = text.replace(f"--set #{m.group(1)} '{texts[k - 1]}'", f"{labels[k - 1]} ({texts[k - 1]})", 1)
        warnings.warn(text, SceneWarning, stacklevel=3)
    return scene


def quiet():
    """The package's programs (sweep, tune, allocate) judge their keys themselves and refuse one that does
    not act: the loader's warnings, one per sample, would only repeat on their console."""
    warnings.simplefilter("ignore", SceneWarning)
