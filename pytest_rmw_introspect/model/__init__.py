"""The model layer: the vocabulary every other layer speaks, defined once.

``vocabulary`` (interface lists, labels, action parts, severities, ``fail_on`` words), ``qos``
(QoS spellings, expansion, compatibility), ``capture`` (the middleware's capture file and the
contract view of it), ``contract`` (contract files: load, validate, render), ``option_tables``
(the comparison and target options, their front ends and precedence) and ``paths`` (how paths
are shown). It may import ``errors`` and nothing else of the package.
"""
