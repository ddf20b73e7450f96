"""One quantity in one place of a spec, whatever its spelling: friction1.mu is
joint1.friction.mu, and a clearance is stored as the journal radius. Two
places would both be recorded while the loader's order let one act (pass 70:
set: contact.clearance beside a dispersed contact.journal_radius; pass 100:
set: joint1.friction.mu beside parameters: friction1.mu; pass 102: the
tuner's set: beside its plants:)."""


def one_quantity(key):
    """The field a scene key sets: a clearance is given as, and stored as, the journal radius
    (bearing_radius - c), so contact.clearance and contact.journal_radius name one quantity."""
    return key[:-len("clearance")] + "journal_radius" if key.endswith("contact.clearance") else key


def quantities_given_twice(sections, aliases):
    """sections: [(section, {key as given: node})], set: first. Two lists of refusals (where, why, node): a
    quantity given twice, refused at once; and one under set: and dispersed in another spelling, refused after
    the refusals of a key that does not act, which say more (under set: in the same spelling the draw acts: the
    set value is the base it replaces)."""
    seen, now, later = {}, [], []  # quantity -> (where, the key as named there)
    for section, mapping in sections:
        for key, node in mapping.items():
            named = aliases.get(key, key)
            if one_quantity(named) in seen:
                where, other = seen[one_quantity(named)]
                same = "the same key as" if named == other else "the same quantity as"
                why = (f"{section}.{key}", f"{same} {where}: give it in one place", node)
                if not (where.startswith("set.") and section != "set"):
                    now.append(why)
                elif where.split(".", 1)[1] != key:
                    later.append(why)
            seen[one_quantity(named)] = (f"{section}.{key}", named)
    return now, later
